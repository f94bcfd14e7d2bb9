"""The soak campaign: long failure-free flights, counting false declarations per flight hour.

Flights: ``--hours H`` at each turbulence level of ``--turbulence`` (one level or a comma
list) and each flight point, cut into ``F = ceil(3600 H / flight_s)`` failure-free flights of
``flight_s`` seconds each (so ``F flight_s >= 3600 H`` hours are flown per point and level),
trimmed at the point.  The points (:func:`soak_points`): ``points`` (objects with ``label``,
``mach``, ``alt_ft``; the CLI takes the envelope campaign's selections ``--points`` and
``--mach-alt``), else the one point ``mach`` / ``alt_ft`` (``--mach``/``--alt-ft``, labelled
:data:`CUSTOM_LABEL`), else the bank's design point (labelled :data:`DESIGN_LABEL`).  The
aircraft holds trim with the dither on, or, with ``maneuvers`` (truth maneuver strings,
``truth.maneuvers``; :func:`profile` gives the ``tour``, each point's from its own flight
condition), every flight flies that schedule: the false declarations are then per hour of
maneuvering flight.
Each flight is one run of the shared engine (runner, store, executor, code identity, lock):
an interrupted soak resumes flight by flight, and flights are distributed like any run.  A soak
without ``points`` plans the flights, specs and run keys it always has; with ``points`` each
spec and record also names its point (``point``), its key differing from point to point by the
scenario's Mach and altitude.

Seeds (common random numbers across levels and points): flight n gets
``evaluation_seed("soak", S, n)`` at every level and every point, so level L1 and level L2
differ in the turbulence intensity only, and point P1 and point P2 in the flight condition only.
Lengthening ``--hours`` keeps the flights already flown.

Per level (``episodes.level_rate``, pooled over the points: the level's false declarations over
its hours at every point), and per point and level (``points``): false declarations per flight
hour with the exact Poisson 95 % interval and the goal's verdict (:data:`GOALS_PER_H`), how long each lasted
(``episodes.false_episodes``) and the hypotheses involved; hours and declarations counted while
the aircraft flies the flight condition (``episodes.left_condition_s``: a flight that leaves it,
e.g. a pilotless aircraft rolling off into a spiral dive, counts up to then, and its later
declarations are reported apart).  ``goals_met``: no level's verdict
is *not met* (pooled).  Every flight with a false declaration is listed with its ``f16mmae run``
command (``drilldown``; with ``points``, with its point).
"""
from __future__ import annotations

import math
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

from ... import __version__
from ...banks import bank_estimator_settings, load_bank
from ...loop.flight import fly, scenario_from_dict
from ...names import FLIGHT_S_MAX, NONE
from ...truth import Scenario
from ...truth.aircraft import check_flight_condition
from ...truth.maneuvers import parse_maneuver
from ..engine import drilldown, identity, outcomes, scoring
from ..engine.config import CampaignConfig, CampaignError
from ..engine.points import check_points
from ..engine.runner import CampaignOutcome, execute, planned_bank
from ..engine.seeds import evaluation_seed
from ..engine.store import ResultsStore, campaign_directory, run_key
from . import episodes, figures

#: The goal per level (issue 14): false declarations per flight hour at most this.
GOALS_PER_H: dict[str, float] = {"none": 0.0, "light": 0.0, "moderate": 0.0, "severe": 1.0}
#: The default flight length (s) a soak is cut into.
SOAK_FLIGHT_S = 600.0
#: The most flights per level a soak plans.
FLIGHTS_MAX = 100_000
#: The label of a soak's one point at the bank's design point (the envelope campaign's nominal point's).
DESIGN_LABEL = "NOM"
#: The label of a soak's one point at ``--mach``/``--alt-ft`` (the first of ``--mach-alt``'s custom points').
CUSTOM_LABEL = "C1"


@dataclass(frozen=True)
class SoakPoint:
    """A flight condition a soak flies: ``label``, Mach and altitude (ft).  ``SoakCampaign.points``
    hold any objects with these three fields (the CLI's are the envelope campaign's points)."""

    label: str
    mach: float
    alt_ft: float


@dataclass(frozen=True)
class SoakCampaign(CampaignConfig):
    """The arguments of ``f16mmae campaign soak`` (``duration_s`` is the length of one flight;
    ``hours`` per point and level)."""

    hours: float = 1.0
    duration_s: float = SOAK_FLIGHT_S
    #: Maneuvers every flight flies (``--maneuver`` strings or :func:`profile`); () holds trim.
    maneuvers: tuple[str, ...] = ()
    #: A named profile (:data:`PROFILES`) flown from the flight condition instead.
    profile: str | None = None
    #: The flight condition every flight starts trimmed at (both or neither); None: the bank's
    #: design point (or the ``points``).
    mach: float | None = None
    alt_ft: float | None = None
    #: The flight points (``label``, ``mach``, ``alt_ft``: the envelope campaign's points), each
    #: flown ``hours`` per level; () the one point of ``mach`` / ``alt_ft`` or the design point.
    points: tuple = ()

    @property
    def flights(self) -> int:
        """Flights per level: ``ceil(3600 hours / duration_s)``."""
        return max(1, math.ceil(round(3600.0 * self.hours / self.duration_s, 9)))

    def validate(self) -> "SoakCampaign":
        if not (isinstance(self.hours, (int, float)) and 0.0 < self.hours < math.inf):
            raise CampaignError(f"--hours must be > 0, got {self.hours!r}")
        if not 0.0 < self.duration_s <= FLIGHT_S_MAX:
            raise CampaignError(f"--flight-s must lie in (0, {FLIGHT_S_MAX:g}] s, got {self.duration_s!r}")
        if self.flights > FLIGHTS_MAX:
            raise CampaignError(f"--hours {self.hours:g} at --flight-s {self.duration_s:g} plans {self.flights} "
                                f"flights per level, more than {FLIGHTS_MAX}: fly longer flights")
        self.check_common(dwell_window_s=self.duration_s)
        if (self.mach is None) != (self.alt_ft is None):
            raise CampaignError("give --mach and --alt-ft together (neither: the bank's design point)")
        if self.mach is not None and self.points:
            raise CampaignError("give --mach/--alt-ft (one flight condition) or --points/--mach-alt "
                                "(flight points), not both")
        if self.mach is not None:
            try:
                check_flight_condition(self.mach, self.alt_ft)
            except ValueError as exc:
                raise CampaignError(f"--mach/--alt-ft: {exc}") from None
        if self.points:
            check_points(self.points)
        if self.profile is not None:
            if self.maneuvers:
                raise CampaignError("give --maneuver or --profile, not both")
            need = profile(self.profile, 0.4, 20_000.0)[1]
            if self.duration_s < need:
                raise CampaignError(f"--profile {self.profile} needs flights of at least {need:g} s (--flight-s)")
        single = (SoakPoint(CUSTOM_LABEL, self.mach, self.alt_ft),) if self.mach is not None else ()
        if self.maneuvers and not (self.points or single):   # at the design point (the plan checks the bank's)
            try:
                Scenario(duration_s=self.duration_s, maneuvers=tuple(self.maneuvers))
            except ValueError as exc:
                raise CampaignError(f"--maneuver: {exc}") from None
        for p in self.points or single:
            check_point_maneuvers(self, p)
        return self


#: Soak profiles: name -> (maneuver strings from Mach M, altitude H ft, the flight length they need).
PROFILES = ("tour", "hold")


def profile(name: str, mach: float, alt_ft: float) -> tuple[tuple[str, ...], float]:
    """The maneuvers of profile ``name`` from (mach, alt_ft) and the flight length (s) they need.

    ``tour`` (540 s): climb 4,000 ft at 2,000 fpm from 10 s (a 30 deg right turn for 60 s from
    60 s, inside the climb), +0.1 Mach at 0.005 Mach/s from 150 s, a 30 deg left turn for 60 s
    from 200 s, descent back at 2,000 fpm from 300 s with the speed back from 350 s, and a
    90-s right turn from 450 s.  The climb goes down and the speed change back first where the
    envelope has no room (within 4,000 ft of 35,000 ft; Mach above 0.7).

    ``hold`` (any length): the pilot's outer loop holds the altitude, the Mach and wings level
    it finds at 0 s for the whole flight (one roll-out to 0 deg bank at 0 s engages it), as a
    pilot or an autopilot does in turbulence; without it a trimmed aircraft left alone for
    minutes in severe turbulence wanders off its design condition (gust_states.md)."""
    if name not in PROFILES:
        raise CampaignError(f"unknown profile {name!r}; valid: {', '.join(PROFILES)}")
    if name == "hold":
        return (str(parse_maneuver("turn@0:bank=0")),), 0.0
    up, down = ("climb", "descend") if alt_ft + 4000 <= 35_000 else ("descend", "climb")
    h1 = alt_ft + 4000 if up == "climb" else alt_ft - 4000
    fast, slow = ("accel", "decel") if mach + 0.1 <= 0.8 else ("decel", "accel")
    m1 = round(mach + 0.1 if fast == "accel" else mach - 0.1, 6)
    texts = (f"{up}@10:to={h1:g}ft:rate=2000fpm", "turn@60:bank=30:for=60",
             f"{fast}@150:to={m1:g}mach:rate=0.005mach/s", "turn@200:bank=-30:for=60",
             f"{down}@300:to={alt_ft:g}ft:rate=2000fpm", f"{slow}@350:to={mach:g}mach:rate=0.005mach/s",
             "turn@450:bank=30:for=90")
    return tuple(str(parse_maneuver(t)) for t in texts), 540.0


def flight_condition(cfg: SoakCampaign, bank) -> tuple[float, float]:
    """(Mach, altitude ft) every flight of a soak without ``points`` starts at:
    ``--mach``/``--alt-ft``, else the design point of ``bank``."""
    if cfg.mach is not None:
        return float(cfg.mach), float(cfg.alt_ft)
    return float(bank.mach), float(bank.alt_ft)


def soak_points(cfg: SoakCampaign, bank) -> tuple:
    """The points ``cfg`` flies with ``bank``, in order: its ``points``, else the one point of
    :func:`flight_condition` (labelled :data:`CUSTOM_LABEL` at ``--mach``/``--alt-ft``, else
    :data:`DESIGN_LABEL`)."""
    if cfg.points:
        return tuple(cfg.points)
    return (SoakPoint(DESIGN_LABEL if cfg.mach is None else CUSTOM_LABEL, *flight_condition(cfg, bank)),)


def point_maneuvers(cfg: SoakCampaign, mach: float, alt_ft: float) -> tuple[str, ...]:
    """The maneuvers every flight of ``cfg`` from (``mach``, ``alt_ft``) flies (a profile's from there)."""
    if cfg.profile is not None:
        return profile(cfg.profile, mach, alt_ft)[0]
    return tuple(cfg.maneuvers)


def flight_maneuvers(cfg: SoakCampaign, bank) -> tuple[str, ...]:
    """The maneuvers every flight of a soak without ``points`` flies with ``bank`` (a profile's
    from the flight condition)."""
    return point_maneuvers(cfg, *flight_condition(cfg, bank))


def check_point_maneuvers(cfg: SoakCampaign, point) -> None:
    """Refuse maneuvers that do not fit a flight from ``point`` (CampaignError naming it)."""
    mans = point_maneuvers(cfg, point.mach, point.alt_ft)
    if not mans:
        return
    try:
        Scenario(mach=float(point.mach), alt_ft=float(point.alt_ft), duration_s=cfg.duration_s, maneuvers=mans)
    except ValueError as exc:
        raise CampaignError(f"point {point.label} (Mach {point.mach:g}, {point.alt_ft:g} ft): "
                            f"maneuvers: {exc}") from None


def flight_seed(campaign_seed: int, index: int) -> int:
    """The seed of flight ``index`` at every level (module docstring)."""
    return evaluation_seed("soak", campaign_seed, index)


# -- one flight (executed in workers) ---------------------------------------------------------
def run_spec(spec: dict) -> dict:
    """Fly one failure-free flight and return its record; a pure function of ``spec``."""
    bank = planned_bank(spec)
    scenario = scenario_from_dict(spec["scenario"])
    result = fly(scenario, bank, estimator_options=spec["estimator"], record_probabilities=False)
    left = episodes.left_condition_s(result.track, scenario.mach, scenario.alt_ft, not scenario.maneuvers)
    flown = scenario.duration_s if left is None else left
    counted = [d for d in result.declarations if left is None or d["time_s"] < left]
    return {
        "run_key": spec["run_key"], "kind": "soak", "level": spec["level"],
        **({"point": spec["point"]} if "point" in spec else {}), "case": NONE,
        "run_index": spec["run_index"], "seed": spec["seed"], "tuning": spec["tuning"], "bank": spec["bank"],
        "bank_hash": spec["bank_hash"], "version": spec["version"], "scenario": spec["scenario"],
        "estimator": spec["estimator"], "estimator_settings": result.estimator_settings,
        "declarations": result.declarations,
        "episodes": episodes.false_episodes(counted, flown),
        **scoring.score_run(NONE, None, counted),
        **outcomes.run_fields(counted, None, {NONE}, flown),
        "left_condition_s": left,
        "declarations_after_leaving": result.declarations[len(counted):],
        "timing": result.timing,
    }


def describe_spec(spec: dict) -> str:
    where = f" at point {spec['point']}" if "point" in spec else ""
    return f"soak flight {spec['run_index']}{where} at {spec['level']} turbulence (seed {spec['seed']})"


def plan(cfg: SoakCampaign, label: str, tuning_arg: str, bank) -> list[dict]:
    """Every flight of ``cfg``: point by point, level by level, flight 0 .. F-1, flight n with
    the same seed everywhere (module docstring).  With ``points`` each spec names its point
    (``point``); the run key is of the flight alone (kind, scenario, estimator, bank, version),
    so a soak without ``points`` keeps the keys it always had."""
    specs = []
    for p in soak_points(cfg, bank):
        mans = point_maneuvers(cfg, p.mach, p.alt_ft)
        for level in cfg.levels():
            for n in range(cfg.flights):
                seed = flight_seed(cfg.seed, n)
                scenario = cfg.scenario_dict(bank, (), seed, mach=p.mach, alt_ft=p.alt_ft, turbulence=level)
                if mans:
                    try:
                        scenario = Scenario.from_dict({**scenario, "maneuvers": list(mans)}).to_dict()
                    except ValueError as exc:
                        raise CampaignError(f"point {p.label} (Mach {scenario['mach']:g}, {scenario['alt_ft']:g} ft): "
                                            f"maneuvers: {exc}") from None
                key = run_key({"kind": "soak", "scenario": scenario, "estimator": cfg.estimator_options(),
                               "bank_hash": bank.content_hash, "version": __version__})
                spec = {"run_key": key, "level": level, "run_index": n, "seed": seed, "tuning": label,
                        "bank": tuning_arg, "bank_hash": bank.content_hash, "version": __version__,
                        "scenario": scenario, "estimator": cfg.estimator_options()}
                if cfg.points:
                    spec["point"] = p.label
                specs.append(spec)
    return specs


# -- the campaign ------------------------------------------------------------------------------
def run_soak(cfg: SoakCampaign, out_dir: str | Path, executor: Executor, executor_label: str = "",
             show_progress: bool = True, allow_mixed: bool = False) -> CampaignOutcome:
    """Plan, fly what is not stored yet, summarize, plot; ``out_dir`` checked and locked first."""
    cfg.validate()
    with campaign_directory(out_dir) as out:
        label, _, bank = load_bank(cfg.tuning)
        specs = plan(cfg, label, cfg.tuning, bank)
        hours_each = cfg.duration_s / 3600.0
        done = execute(specs, ResultsStore(out), executor, run_spec, describe=describe_spec,
                       progress_label="flights", show_progress=show_progress, allow_mixed=allow_mixed,
                       progress_note=lambda n: f"({n * hours_each:.2f}/{len(specs) * hours_each:.2f} h flown)")
        points = soak_points(cfg, bank)
        records = with_points(points, done.records)
        summary = summarize(cfg, label, bank, records)
        summary["figures"] = figures.make_figures(out, records, summary)
        return done.finish(out, summary, executor_label)


def with_points(points, records: list[dict]) -> list[dict]:
    """``records`` each with ``point``: the label of the point of ``points`` it flew from, by
    its scenario's Mach and altitude (a flight stored under another label, e.g. ``--points NOM``
    flown again as ``--mach-alt 0.4:20000``, is the same flight and takes this soak's label).
    CampaignError for a record from none of them."""
    where = {(round(float(p.mach), 6), round(float(p.alt_ft), 3)): p.label for p in points}
    out = []
    for r in records:
        condition = (round(float(r["scenario"]["mach"]), 6), round(float(r["scenario"]["alt_ft"]), 3))
        if condition not in where:
            raise CampaignError(f"soak flight {r['run_key']} flew Mach {condition[0]:g}, {condition[1]:g} ft: "
                                f"none of the points {', '.join(where.values())}")
        out.append({**r, "point": where[condition]})
    return out


def summarize(cfg: SoakCampaign, label: str, bank, records: list[dict]) -> dict:
    """The soak's ``summary.json`` from its flight records (module docstring): per level pooled
    over the points (``levels``), per point and level (``points``, in the points' order), the
    top-level ``mach`` / ``alt_ft`` the one point's (None over several)."""
    points = soak_points(cfg, bank)
    labelled = bool(cfg.points)
    where = {p.label: i for i, p in enumerate(points)}
    order = {lvl: i for i, lvl in enumerate(cfg.levels())}
    ranked = sorted(with_points(points, records),
                    key=lambda r: (where[r["point"]], order.get(r["level"], len(order)), r["run_index"]))
    levels = []
    for lvl in cfg.levels():
        rate = episodes.level_rate([r for r in ranked if r["level"] == lvl], GOALS_PER_H[lvl])
        levels.append({"level": lvl, **rate})
    by_point = []
    for p in points:
        mans = point_maneuvers(cfg, p.mach, p.alt_ft)
        rows = [{"level": lvl, **episodes.level_rate([r for r in ranked if r["point"] == p.label and r["level"] == lvl],
                                                     GOALS_PER_H[lvl])} for lvl in cfg.levels()]
        by_point.append({"label": p.label, "mach": float(p.mach), "alt_ft": float(p.alt_ft),
                         "maneuvers": list(mans) or None, "levels": rows})
    verdicts = {lv["level"]: lv["per_hour"].get("verdict") for lv in levels}
    single = points[0] if len(points) == 1 else None
    schedules = {tuple(p["maneuvers"] or ()) for p in by_point}
    where_label = (lambda r: {"point": r["point"]}) if labelled else (lambda r: {})
    return {
        "kind": "soak", "seed": cfg.seed, "hours": cfg.hours, "flight_s": cfg.duration_s,
        "flights_per_level": cfg.flights, "turbulence": cfg.turbulence, "levels": levels,
        "points": by_point,
        "tuning": label, "bank_hash": bank.content_hash, "version": __version__,
        "mach": None if single is None else float(single.mach),
        "alt_ft": None if single is None else float(single.alt_ft),
        "design_point": {"mach": float(bank.mach), "alt_ft": float(bank.alt_ft)},
        "feedback": cfg.feedback,
        "dither": cfg.dither, "dither_scale": cfg.dither_scale,
        "maneuvers": (list(schedules.pop()) or None) if len(schedules) == 1 else None,
        "profile": cfg.profile,
        "estimator": cfg.estimator_options(),
        "estimator_settings": bank_estimator_settings(bank, cfg.estimator_options()),
        "goals_per_hour": {lvl: GOALS_PER_H[lvl] for lvl in cfg.levels()},
        "verdicts": verdicts,
        "goals_met": all(v is not None and v != "not met" for v in verdicts.values()),
        "code": identity.code_identity(),
        "left_condition": [
            {**where_label(r), "level": r["level"], "run_index": r["run_index"], "seed": r["seed"],
             "left_condition_s": r["left_condition_s"], "declarations_after_leaving": r["declarations_after_leaving"],
             "command": drilldown.record_command(r, cfg.dither_scale)}
            for r in ranked if r.get("left_condition_s") is not None],
        "not_clean": drilldown.not_clean(
            ranked, lambda r: drilldown.record_command(r, cfg.dither_scale),
            lambda r: {**where_label(r), "level": r["level"], "false_declarations": r["false_declarations"],
                       "episodes": r["episodes"]}),
    }
