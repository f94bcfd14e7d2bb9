"""The turbulence bank set: hierarchical banks designed per turbulence intensity, flown as one
estimator that selects the running bank on line by the intensity it measures
(cpp/f16mmae/turbulence_bank_set.h; ``--turbulence-banks``).

Members (``MEMBER_LEVELS``): the tuning ``MEMBER_TUNING`` with the throttle command as the
sixth input (``design_bank(..., throttle_input=True)``), its gust model designed for calm air
and for light turbulence, at the nominal point; one state vector for all (a copied standby
starts from the states of the member in force).  The light member, its turbulence adaptation
tempering up to its bound, also flies moderate and severe turbulence: members designed for
those (the set had four until 2026-11-30) declared the flaperons falsely at their own level,
which no reference of theirs removed without losing LF/RF isolation, while the light member
tempering at s = 4.6 in moderate turbulence was quiet and isolated as well (tuning seeds,
docs/results/turbulence_banks.md).  ``tuned_gust`` (19 states:
the six Dryden gust states) and not ``tuned`` (13): with 13-state members the light member
alone declared 50 false failures in 0.67 h of light turbulence and the set 609 at moderate
(docs/results/turbulence_banks.md).

The artifact is one turbulence-bank-set file ``turbulence_banks_<key>.f16set``
(cpp/bankfile/turbulence_set_file.h: the member bank files whole, each member's level,
adaptation reference and gain and trim tracking, the selector's settings, the load-factor tempering the
set is flown with, hashed), read and validated by the one C++
loader that ``mmae-daemon --turbulence-banks`` uses too; its content hash (``set_hash``) names
the set in the daemon's status.  Deterministic: the same code and truth give the same file (the
design is).  Not committed (0.6 MB): :func:`set_path` is generated on first use into
the cache (``$F16MMAE_CACHE_DIR`` or ``~/.cache/f16mmae``, ``banks/``), or written by
``f16mmae design --turbulence-banks --out FILE``.

The selector's boundaries are each member's own averaged residual power ratio rho (the
turbulence adaptation's, turbulence_adaptation.h) measured flying every member at every level
on tuning seeds (``tools/turbulence_banks.py``; docs/results/turbulence_banks.md): ``BOUNDS``
row a lies between member a's median rho at consecutive levels (``MEDIAN_RHO``).
"""
from __future__ import annotations

import fcntl
import functools
import hashlib
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .. import names
from ..cache import cache_root
from ..errors import F16mmaeError

#: The members' levels (the air each is chosen for), in rising intensity, and their tuning.
MEMBER_LEVELS: tuple[str, ...] = ("none", "light")
MEMBER_TUNING = "tuned_gust"
#: The gust level each member's bank is designed for (members designed for moderate and severe
#: gusts declared the flaperons falsely at their own level; the light design tempers there
#: instead, below).  A member for stronger air may take the light design with its own floor
#: (``MEMBER_P_MIN``).
MEMBER_DESIGN_LEVEL: tuple[str, ...] = ("none", "light")
#: Each member's probability floor (its bank file's recommended p_min): the tuning's 1e-9.  A
#: floor of 1e-6 in a member for light and moderate air (with a severe member at 1e-9) shortened
#: the latency there but declared falsely in severe turbulence before the hand-over, and a
#: separate moderate member lost more at its hand-over than the floor gained in 8-s flights
#: (tuning seeds, docs/results/turbulence_banks.md, round 9): not adopted.
MEMBER_P_MIN: tuple[float, ...] = (1e-9, 1e-9)
#: Each member's failure model (design/hypotheses.py) for its level-0 hypotheses (NONE and the
#: twelve single failures), and the one model of every member's level-1 (dual) hypotheses.
#: ``constant=VEL`` in every member and level (a failed VEL reads an unknown constant near its
#: trim) found VEL in calm air and light turbulence 10 of 10 (from 8) but its duals X+VEL took
#: the speed transient after a stabilator failure (transient-wrong declarations at none, light
#: and moderate) and severe turbulence lost 6 of 130 (evaluation seeds,
#: docs/results/turbulence_banks.md, round 9).  ``constant=VEL`` at level 0 only (the duals
#: ``complete``, the gain 25 and the selector's bounds re-measured with it) found VEL 10 of 10 in
#: calm air and light turbulence, but the constant hypothesis was declared before the failure in
#: light and severe turbulence (transient-wrong runs) and lost VEL in severe turbulence (4 of 10):
#: correct 128 / 128 / 130 / 103 of 130 against 127 / 128 / 130 / 109 (evaluation seeds, round 10):
#: not adopted.
MEMBER_FAILURE_MODEL: tuple[str, ...] = ("complete", "complete")
DUAL_FAILURE_MODEL = "complete"
#: The member in force at the start (light, the shipped design level) and the one running
#: beside it from frame 0 (calm air: handed over within seconds when the air is calm).
START = 1
START_STANDBY = 0
#: Each member's (row) median rho flown in each member's level (column): tuning flight seeds 1-8,
#: 60 s each, after 10 s (tools/turbulence_banks.py; docs/results/turbulence_banks.md).  Members
#: with the constant VEL hypothesis read lower, 0.68 / 2.93 and 0.58 / 0.71 (round 10), and need
#: their own: with the bounds below their light member handed light air to the calm member in the
#: first seconds of a flight, which declared VEL.
MEDIAN_RHO: tuple[tuple[float, ...], ...] = (
    (0.70, 3.47),
    (0.58, 0.74),
)
#: The selector's boundaries: member a's rho between levels i and i+1, the geometric mean of
#: its medians there (row-major, n x (n-1)); a standby starts at its own level's median.
#: The calm member's own bound (``CALM_BOUND``) replaces its geometric mean (1.56): with the rule
#: ``CALMER_OWN_RHO`` it decides both ways between calm air and light turbulence, the calm
#: member's rho in calm air (median 0.70) below it and in light turbulence (median 3.47) far
#: above it.
CALM_BOUND = 0.95
BOUNDS: tuple[float, ...] = (CALM_BOUND,) + tuple(round((row[i] * row[i + 1]) ** 0.5, 4)
                                                  for row in MEDIAN_RHO[1:] for i in range(len(row) - 1))
#: The selector's rule ``calmer_own_rho`` (turbulence_bank_set.h): while the calm member runs
#: beside the light one (from frame 0, or as a copy), its own rho against its own bound decides
#: whether it takes over, not the light member's, whose rho in calm air (median 0.58) lies close
#: to its bound (0.655) where the calm member's lies far from it.
CALMER_OWN_RHO = True
TYPICAL: tuple[float, ...] = tuple(MEDIAN_RHO[i][i] for i in range(len(MEDIAN_RHO)))
#: The selector's floor by rho (turbulence_bank_set.h): each member's level-0 floor while its own
#: rho is at or below ``FLOOR_RHO`` (0: off), ``FLOOR_P_MIN`` (0: the member's own,
#: ``MEMBER_P_MIN``), its own above and while a failure rises or is declared.  The light member
#: at 1e-6 below 2.68 (the geometric mean of its median rho at moderate and severe, 1.18 and
#: 6.08), the calm member at its own: the moderate latency median 0.53 -> 0.48 s VEL excepted and
#: light 128 -> 129 of 130, severe unchanged, 0 false declarations in 10 h at none, light and
#: moderate, severe held as before; with the raised floor held at level 1 a dual was declared
#: after a correct declaration at moderate and VEL backed out at light, which the own floor while
#: frozen removed (docs/results/turbulence_banks.md, round 12).  0 turns it off (revision 16).
FLOOR_RHO = 2.68
FLOOR_P_MIN: tuple[float, ...] = (0.0, 1e-6)
HOLD_S = 1.0
WARM_UP_S = 1.0
WARM_DOWN_S = 5.0
SETTLE_S = 1.0
FREEZE_PROBABILITY = 0.05
#: Each member's turbulence-adaptation reference rho_0 (tempering above it only): the calm
#: member's 1.0, as the single light gust bank's (gust_states.md), against its own 99th
#: percentile at its level; the light member's 1.05, which tempers moderate turbulence (its rho
#: there: median 1.19, 1st percentile 1.09) less and leaves light air (99th percentile 0.79) and
#: severe turbulence (s at its bound) as they were.  1.1 shortened the moderate latency further
#: but a dual declared falsely after an AOA failure (a transient-wrong run; evaluation seeds,
#: docs/results/turbulence_banks.md, round 10): not adopted.
ADAPT_REFERENCE: tuple[float, ...] = (1.0, 1.05)
#: Each member's adaptation gain kappa (s = 1 + kappa (rho - rho_0), turbulence_adaptation.h): the
#: core's default, 20.  Members with the constant VEL hypothesis need 25: that hypothesis leaves
#: the VEL channel's gust share out of its quadratic form, so rho, the minimum over the
#: hypotheses, reads 4-13 % lower in turbulence, and at 20 they tempered less in severe turbulence
#: and declared falsely there (2 in 1.33 h held, 0 at 25; tuning seeds,
#: docs/results/turbulence_banks.md, round 10).
ADAPT_GAIN: tuple[float, ...] = (20.0,) * len(MEMBER_LEVELS)
#: Each member's trim tracking time constant (trim_tracker.h), s: slow enough not to follow a stuck
#: airspeed within the seconds its hypothesis needs, fast enough for the trimmed aircraft's drift
#: over minutes, which the calm member read as AOA failures late in long flights (tuning seeds:
#: docs/results/turbulence_banks.md). --trim-tracking TAU overrides it in every member.
TRIM_TIME_CONSTANT_S: tuple[float, ...] = (300.0,) * len(MEMBER_LEVELS)
#: The declaration dwell each member's bank file recommends (s; the tuning's is 0.25): the
#: latency median 0.62 -> 0.50 s at light, 0.69 -> 0.56 s at moderate, the same correct counts
#: and no transient-wrong declaration, 0 false declarations in 10 h at none, light and moderate,
#: 0.50/h in severe turbulence held (0.40/h at 0.25 s); evaluation seeds,
#: docs/results/turbulence_banks.md. --dwell-s overrides it.
DWELL_S = 0.125
#: The load-factor tempering the set is flown with (n_ref, g; maneuver_kinematics.h), carried in the
#: set file: in severe turbulence with the pilot holding it took the false declarations from 2.30 to
#: 0.40 per hour, light and moderate as before (docs/results/turbulence_banks.md).
#: --maneuver-tempering G overrides it.
MANEUVER_TEMPERING_G = 1.0


#: Bumped whenever the members' design or the thresholds change (part of the cache key).
REVISION = 17
SUFFIX = ".f16set"


class BankSetError(F16mmaeError):
    """A turbulence bank set cannot be found, designed or loaded; the message names the file."""


@dataclass(frozen=True)
class BankSet:
    """A loaded, checked set: the member banks (core.ModelBank, rising intensity) and the
    selector's settings (keyword arguments of core.TurbulenceBankSet), the set's hash, and the
    file itself (``source``, core.TurbulenceSetFile: what core.Executive runs)."""
    path: Path
    levels: tuple[str, ...]
    banks: tuple
    adapt_reference: tuple[float, ...]
    adapt_gain: tuple[float, ...]
    trim_time_constant_s: tuple[float, ...]
    maneuver_tempering_g: float
    selector: dict
    set_hash: str
    source: object


def set_path() -> Path:
    """Where the set is cached; its name carries a hash of the revision, the levels, the
    thresholds and the shipped tuned bank (which changes when the truth or the tuning does)."""
    with open(names_data_dir() / "nominal_tuned.f16bank", "rb") as f:
        header = f.read(52)
    spec = (f"{REVISION};{MEMBER_TUNING};{MEMBER_LEVELS};{BOUNDS};{TYPICAL};{HOLD_S};{WARM_UP_S};{WARM_DOWN_S};{SETTLE_S};"
            f"{FREEZE_PROBABILITY};{ADAPT_REFERENCE};{ADAPT_GAIN};{TRIM_TIME_CONSTANT_S};{START};{START_STANDBY};"
            f"{MANEUVER_TEMPERING_G};{DWELL_S};{MEMBER_FAILURE_MODEL};{DUAL_FAILURE_MODEL};{MEMBER_DESIGN_LEVEL};{MEMBER_P_MIN};{CALMER_OWN_RHO};"
            f"{FLOOR_RHO};{FLOOR_P_MIN}")
    key = hashlib.sha256(spec.encode() + header[20:52]).hexdigest()[:16]
    return cache_root() / "banks" / f"turbulence_banks_{key}{SUFFIX}"


def names_data_dir() -> Path:
    from ..banks import DATA_DIR

    return DATA_DIR


def design_set(out: str | Path, progress=None) -> Path:
    """Design the members and write the set file ``out`` (atomically: a half-written set is
    never found).  Returns ``out``."""
    from .. import core
    from .bank import NOMINAL_ALT_FT, NOMINAL_MACH, design_bank, write_bank
    from .model import linearize_truth
    from .hypotheses import check_failure_model
    from .tuning import load_tuning

    import dataclasses

    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    base = load_tuning(MEMBER_TUNING)
    lin = linearize_truth(NOMINAL_MACH, NOMINAL_ALT_FT, throttle=True)
    members = []
    with tempfile.TemporaryDirectory(prefix=out.name + ".", dir=out.parent) as tmp:
        for level, design_level, p_min, model in zip(MEMBER_LEVELS, MEMBER_DESIGN_LEVEL, MEMBER_P_MIN,
                                                     MEMBER_FAILURE_MODEL):
            tuning = base if design_level == base.turbulence else dataclasses.replace(
                base, name=f"{base.name}-{design_level}", turbulence=design_level)
            tuning = dataclasses.replace(tuning, failure_model=check_failure_model(model),
                                         estimator={**{k: v for k, v in tuning.estimator.items()   # no evidence
                                                       if k != "dwell_nats_per_hypothesis"},   # dwell: the nominal bank's
                                                    "dwell_s": DWELL_S, "p_min": p_min})
            design = design_bank(NOMINAL_MACH, NOMINAL_ALT_FT, tuning, linearized=lin, throttle_input=True)
            design = _with_dual_model(design, check_failure_model(DUAL_FAILURE_MODEL), lin)
            bank = write_bank(design, Path(tmp) / f"{level}.f16bank")
            members.append(bank)
            if progress:
                progress(f"member {level}: content hash {bank.content_hash}")
    selector = {"bounds": list(BOUNDS), "typical": list(TYPICAL), "hold_s": HOLD_S, "warm_up_s": WARM_UP_S,
                "warm_down_s": WARM_DOWN_S, "settle_s": SETTLE_S, "freeze_probability": FREEZE_PROBABILITY,
                "start": START, "start_standby": START_STANDBY, "calmer_own_rho": CALMER_OWN_RHO,
                "floor_rho": FLOOR_RHO, "floor_p_min": list(FLOOR_P_MIN)}
    try:
        core.save_turbulence_set(out, members, levels=list(MEMBER_LEVELS), adapt_reference=list(ADAPT_REFERENCE),
                                 trim_time_constant_s=list(TRIM_TIME_CONSTANT_S), selector=selector,
                                 maneuver_tempering_g=MANEUVER_TEMPERING_G, adapt_gain=list(ADAPT_GAIN))
    except (OSError, ValueError) as exc:
        raise BankSetError(f"cannot write the turbulence bank set {out}: {exc}") from None
    return out


def _with_dual_model(design, dual_model: str, lin):
    """``design`` with its level-1 (dual) filters those of the same design in ``dual_model``
    (its level-0 filters as designed); the design itself when the models agree.  The tuning's
    description records the split (the bank's metadata)."""
    import dataclasses

    from .bank import design_bank

    if design.tuning.failure_model == dual_model:
        return design
    duals = design_bank(design.mach, design.alt_ft, dataclasses.replace(design.tuning, failure_model=dual_model),
                        linearized=lin, throttle_input=design.throttle_input)
    filters = tuple(d if "+" in f.model.name else f for f, d in zip(design.filters, duals.filters, strict=True))
    tuning = dataclasses.replace(design.tuning, description=(
        f"{design.tuning.description} Level-0 hypotheses: failure model {design.tuning.failure_model}; "
        f"level-1 (dual) hypotheses: {dual_model}.").strip())
    return dataclasses.replace(design, tuning=tuning, filters=filters)


def load_set(path: str | Path | None = None) -> BankSet:
    """The set file ``path`` (default: :func:`set_path`, designed first if missing), checked by
    the C++ loader: BankSetError naming the file and the field for a missing or damaged file
    or a field out of its range."""
    if path is None:
        path = set_path()
        if not path.is_file():
            path.parent.mkdir(parents=True, exist_ok=True)
            with open(path.parent / (path.name + ".lock"), "w") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)   # one process designs; the others wait and load it
                if not path.is_file():
                    print(f"designing the turbulence bank set ({', '.join(MEMBER_LEVELS)}) into {path} "
                          "(once; cached)...", file=sys.stderr, flush=True)
                    design_set(path, progress=lambda line: print("  " + line, file=sys.stderr, flush=True))
    path = Path(path)
    try:
        f = _load_set_cached(str(path.resolve()), path.stat().st_mtime_ns)
    except (OSError, ValueError) as exc:
        raise BankSetError(f"cannot load the turbulence bank set {path}: {exc}") from None
    unknown = [x for x in f.levels if x not in names.TURBULENCE_LEVELS]
    if unknown:
        raise BankSetError(f"turbulence bank set {path}: levels {unknown} are not turbulence levels "
                           f"({', '.join(names.TURBULENCE_LEVELS)})")
    return BankSet(path=path, levels=tuple(f.levels), banks=tuple(f.members),
                   adapt_reference=tuple(f.adapt_reference), adapt_gain=tuple(f.adapt_gain),
                   trim_time_constant_s=tuple(f.trim_time_constant_s),
                   maneuver_tempering_g=float(f.maneuver_tempering_g),
                   selector=dict(f.selector), set_hash=f.content_hash,
                   source=f)


@functools.lru_cache(maxsize=4)
def _load_set_cached(path: str, mtime_ns: int):
    from .. import core

    return core.load_turbulence_set(path)


def _start_member():
    """The set file's path and its start member (core.ModelBank): the bank the loop flies."""
    s = load_set()
    return s.path, s.banks[s.selector["start"]]


def _register() -> None:
    from .. import banks

    banks.register_turbulence_set(load_set, _start_member)


_register()
