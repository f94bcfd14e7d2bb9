"""Scenario: everything that defines one truth-model run, as plain data (TOML in, dict out).

Fields: mach (0.3-0.8), alt_ft (5,000-35,000), turbulence (none|light|moderate|severe),
dither (DitherSpec), failures (tuple of FailureSpec, at most one per component), duration_s
(> 0), seed (integer >= 1; JSBSim maps 0 to 1, so seeds start at 1), feedback ("mmae": the FCS
flies on the estimator's z_hat, the paper's MMAE-based control; "raw": on the sensors), ari
(aileron-to-rudder interconnect on/off), noise (sensor noise on/off), gust_burst (optional
``turbulence.GustBurst``: another turbulence level for a while; ``"LEVEL@START+DURATION"`` or a
table level, start_s, duration_s; absent from ``to_dict`` when there is none), maneuvers (tuple of
ManeuverSpec, the pilot's schedule: ``truth.maneuvers``; none by default, and then the flight
is the unmaneuvered one).

TOML (``Scenario.from_toml``)::

    mach = 0.4
    alt_ft = 20000
    turbulence = "light"
    duration_s = 8.0
    seed = 7
    feedback = "mmae"
    ari = true
    failures = ["LS@3.0", "PIT@5.0:stuck"]      # CLI syntax, or tables
    maneuvers = ["climb@5:to=25000ft:rate=3000fpm", "turn@20:bank=30"]   # truth.maneuvers
    [[failure]]                                 # ([[failures]] too): name, time_s, mode, value
    name = "AZ"
    time_s = 2.0
    mode = "bias"
    value = 0.2
    [dither]
    enabled = true
    amplitude_deg = [0.8, 0.8, 0.6, 0.6, 1.6]
    frequency_hz = [1.3, 1.7, 1.1, 1.5, 0.9]

Unknown keys, names, modes, out-of-range values are refused with ValueError naming the valid
choices.  ``parse_fail`` (the CLI's ``--fail NAME@TIME[:MODE[=VALUE]]``) lives in
``truth.failures`` and is re-exported here.
"""
from __future__ import annotations

import math

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..names import FEEDBACK_MODES
from . import aircraft, turbulence
from .dither import DitherSpec
from .failures import FailureSpec, check_unique, make_failure, parse_fail, parse_fail_args
from .maneuvers import ManeuverSpec, check_schedule, parse_maneuver

#: Folder of the example scenarios shipped with the package (``f16mmae/scenarios/*.toml``).
EXAMPLES_DIR = Path(__file__).resolve().parent.parent / "scenarios"
_KEYS = ("mach", "alt_ft", "turbulence", "dither", "failures", "failure", "duration_s", "seed",
         "feedback", "ari", "noise", "gust_burst", "maneuvers")
_DITHER_KEYS = ("enabled", "amplitude_deg", "frequency_hz", "phase_rad", "throttle_amplitude",
                "throttle_frequency_hz", "throttle_schedule")
_FAILURE_KEYS = ("name", "time_s", "mode", "value")


@dataclass(frozen=True)
class Scenario:
    """One run's definition (see module docstring).  Validated on construction."""

    mach: float = 0.4
    alt_ft: float = 20_000.0
    turbulence: str = "none"
    dither: DitherSpec = field(default_factory=DitherSpec)
    failures: tuple[FailureSpec, ...] = ()
    duration_s: float = 8.0
    seed: int = 1
    feedback: str = "mmae"
    ari: bool = True
    noise: bool = True
    gust_burst: turbulence.GustBurst | None = None
    maneuvers: tuple[ManeuverSpec, ...] = ()

    def __post_init__(self):
        aircraft.check_flight_condition(float(self.mach), float(self.alt_ft))
        object.__setattr__(self, "mach", float(self.mach))
        object.__setattr__(self, "alt_ft", float(self.alt_ft))
        object.__setattr__(self, "turbulence", turbulence.check_level(self.turbulence))
        if not isinstance(self.dither, DitherSpec):
            raise ValueError(f"dither must be a DitherSpec, got {type(self.dither).__name__}")
        fails = tuple(self.failures)
        for f in fails:
            if not isinstance(f, FailureSpec):
                raise ValueError(f"failures must be FailureSpec objects, got {f!r}")
        fails = tuple(sorted(fails, key=lambda f: f.time_s))
        check_unique(fails)
        object.__setattr__(self, "failures", fails)
        d = float(self.duration_s)
        if not math.isfinite(d) or d <= 0.0:
            raise ValueError(f"duration_s must be a positive number of seconds, got {self.duration_s}")
        object.__setattr__(self, "duration_s", d)
        for f in fails:
            if f.time_s > d:
                raise ValueError(f"failure {f} starts after the end of the run ({d:g} s)")
        if isinstance(self.seed, bool) or int(self.seed) != self.seed or int(self.seed) < 1:
            raise ValueError(f"seed must be an integer >= 1 (JSBSim treats 0 as 1), got {self.seed!r}")
        object.__setattr__(self, "seed", int(self.seed))
        fb = str(self.feedback).lower()
        if fb not in FEEDBACK_MODES:
            raise ValueError(f"unknown feedback {self.feedback!r}; valid: {', '.join(FEEDBACK_MODES)}")
        object.__setattr__(self, "feedback", fb)
        for name in ("ari", "noise"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name} must be true or false, got {getattr(self, name)!r}")
        burst = self.gust_burst
        if isinstance(burst, str):
            burst = turbulence.GustBurst.parse(burst)
        elif isinstance(burst, dict):
            bad = sorted(set(burst) - {"level", "start_s", "duration_s"})
            if bad or len(burst) != 3:
                raise ValueError(f"a gust_burst table needs exactly level, start_s, duration_s; got {burst}")
            burst = turbulence.GustBurst(**burst)
        elif burst is not None and not isinstance(burst, turbulence.GustBurst):
            raise ValueError(f"gust_burst must be 'LEVEL@START+DURATION' or a table, got {burst!r}")
        if burst is not None and burst.start_s >= d:
            raise ValueError(f"gust burst {burst.text()} starts after the end of the run ({d:g} s)")
        object.__setattr__(self, "gust_burst", burst)
        if isinstance(self.maneuvers, str):
            raise ValueError(f"maneuvers must be a list of strings, got the string {self.maneuvers!r}")
        ms = check_schedule(self.maneuvers, self.mach, self.alt_ft)
        for m in ms:
            if m.time_s > d:
                raise ValueError(f"maneuver {m} starts after the end of the run ({d:g} s)")
        object.__setattr__(self, "maneuvers", ms)

    # -- conversions -------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain data (JSON/TOML-ready) that ``from_dict`` reads back to an equal Scenario;
        ``maneuvers`` (canonical strings) only when there are some, so an unmaneuvered
        scenario's record is what it always was."""
        out = {"mach": self.mach, "alt_ft": self.alt_ft, "turbulence": self.turbulence,
                "duration_s": self.duration_s, "seed": self.seed, "feedback": self.feedback,
                "ari": self.ari, "noise": self.noise, "dither": self.dither.to_dict(),
                "failures": [f.to_dict() for f in self.failures]}
        if self.gust_burst is not None:
            out["gust_burst"] = self.gust_burst.to_dict()
        if self.maneuvers:
            out["maneuvers"] = [str(m) for m in self.maneuvers]
        return out

    @classmethod
    def from_dict(cls, data: dict) -> "Scenario":
        """Build from plain data (the TOML layout of the module docstring)."""
        unknown = sorted(set(data) - set(_KEYS))
        if unknown:
            raise ValueError(f"unknown scenario key(s) {', '.join(unknown)}; valid: {', '.join(_KEYS)}")
        kw = {k: data[k] for k in ("mach", "alt_ft", "turbulence", "duration_s", "seed",
                                   "feedback", "ari", "noise", "gust_burst") if k in data}
        if "dither" in data:
            dd = data["dither"]
            if isinstance(dd, bool):
                kw["dither"] = DitherSpec(enabled=dd)
            else:
                bad = sorted(set(dd) - set(_DITHER_KEYS))
                if bad:
                    raise ValueError(f"unknown dither key(s) {', '.join(bad)}; valid: {', '.join(_DITHER_KEYS)}")
                kw["dither"] = DitherSpec(**dd)
        fails = []
        for t in list(data.get("failures", [])) + list(data.get("failure", [])):
            if isinstance(t, str):
                fails.append(parse_fail(t))
                continue
            if isinstance(t, FailureSpec):
                fails.append(t)
                continue
            if not isinstance(t, dict):
                raise ValueError(f"a failure must be a 'NAME@TIME[:MODE]' string or a table, got {t!r}")
            bad = sorted(set(t) - set(_FAILURE_KEYS))
            if bad:
                raise ValueError(f"unknown failure key(s) {', '.join(bad)}; valid: {', '.join(_FAILURE_KEYS)}")
            if "name" not in t or "time_s" not in t:
                raise ValueError(f"a [[failure]] table needs name and time_s, got {t}")
            fails.append(make_failure(t["name"], t["time_s"], t.get("mode"), t.get("value")))
        kw["failures"] = tuple(fails)
        mans = data.get("maneuvers", [])
        if isinstance(mans, str) or not isinstance(mans, (list, tuple)):
            raise ValueError(f"maneuvers must be a list of strings like 'climb@5:to=25000ft', got {mans!r}")
        kw["maneuvers"] = tuple(m if isinstance(m, ManeuverSpec) else parse_maneuver(m) for m in mans)
        return cls(**kw)

    @classmethod
    def from_toml(cls, source: str | Path) -> "Scenario":
        """Load from a TOML file path (or TOML text if ``source`` contains a newline or '=')."""
        text = str(source)
        if isinstance(source, Path) or ("\n" not in text and "=" not in text):
            path = Path(source)
            if not path.is_file():
                raise ValueError(f"scenario file {path} does not exist")
            text = path.read_text()
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"scenario is not valid TOML: {exc}") from None
        return cls.from_dict(data)

    def with_maneuvers(self, specs) -> "Scenario":
        """A copy with ``specs`` (ManeuverSpec or ``--maneuver`` strings) added."""
        extra = tuple(parse_maneuver(s) if isinstance(s, str) else s for s in specs)
        return replace(self, maneuvers=self.maneuvers + extra)

    def with_failures(self, specs) -> "Scenario":
        """A copy with ``specs`` (FailureSpec or ``--fail`` strings) added."""
        extra = tuple(parse_fail(s) if isinstance(s, str) else s for s in specs)
        return replace(self, failures=self.failures + extra)


def example(name: str) -> Scenario:
    """Load a shipped example scenario by stem (``nominal``, ``single_ls``, ...)."""
    names = sorted(p.stem for p in EXAMPLES_DIR.glob("*.toml"))
    if name not in names:
        raise ValueError(f"unknown example scenario {name!r}; valid: {', '.join(names)}")
    return Scenario.from_toml(EXAMPLES_DIR / f"{name}.toml")


__all__ = ["Scenario", "example", "EXAMPLES_DIR", "FEEDBACK_MODES", "FailureSpec", "parse_fail", "parse_fail_args", "make_failure"]
