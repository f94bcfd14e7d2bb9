"""The turbulence bank set: hierarchical banks designed per turbulence intensity, flown as one
estimator that selects the running bank on line by the intensity it measures
(cpp/f16mmae/turbulence_bank_set.h; ``--turbulence-banks``).

Members (``MEMBER_LEVELS``): the tuning ``MEMBER_TUNING`` with the throttle command as the
sixth input (``design_bank(..., throttle_input=True)``), its gust model designed for calm air,
light, moderate and severe turbulence, at the nominal point; one state vector for all (a
copied standby starts from the states of the member in force).  ``tuned_gust`` (19 states:
the six Dryden gust states) and not ``tuned`` (13): with 13-state members the light member
alone declared 50 false failures in 0.67 h of light turbulence and the set 609 at moderate
(docs/results/turbulence_banks.md).

The artifact is one directory ``turbulence_banks_<key>/``: the member bank files and
``set.json``, which names each member's file with its SHA-256 and content hash, the selector's
thresholds and its own SHA-256 over all of that (``set_hash``).  :func:`load_set` checks every
hash and field and refuses, naming the file and field, anything else.  Deterministic: the same
code and truth give the same files (the design is).  Not committed (four banks, 1.2 MB):
:func:`set_path` is generated on first use into the cache (``$F16MMAE_CACHE_DIR`` or
``~/.cache/f16mmae``, ``banks/``), or written by ``f16mmae design --turbulence-banks --out DIR``.

The selector's boundaries are each member's own averaged residual power ratio rho (the
turbulence adaptation's, turbulence_adaptation.h) measured flying every member at every level
on tuning seeds (``tools/turbulence_banks.py``; docs/results/turbulence_banks.md): ``BOUNDS``
row a lies between member a's median rho at consecutive levels (``MEDIAN_RHO``).
"""
from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .. import names
from ..errors import F16mmaeError

#: The members' design levels, in rising intensity, and their tuning.
MEMBER_LEVELS: tuple[str, ...] = ("none", "light", "moderate", "severe")
MEMBER_TUNING = "tuned_gust"
#: The member in force at the start (light, the shipped design level) and the one running
#: beside it from frame 0 (calm air: handed over within seconds when the air is calm).
START = 1
START_STANDBY = 0
#: Each member's (row) median rho flown in each level (column), none..severe: tuning flight
#: seeds 1-8, 60 s each, after 10 s (tools/turbulence_banks.py; docs/results/turbulence_banks.md).
MEDIAN_RHO: tuple[tuple[float, ...], ...] = (
    (0.70, 3.47, 11.63, 84.51),
    (0.58, 0.74, 1.18, 6.08),
    (0.49, 0.57, 0.80, 3.22),
    (0.33, 0.35, 0.41, 1.14),
)
#: The selector's boundaries: member a's rho between levels i and i+1, the geometric mean of
#: its medians there (row-major, n x (n-1)); a standby starts at its own level's median.
BOUNDS: tuple[float, ...] = tuple(round((row[i] * row[i + 1]) ** 0.5, 4) for row in MEDIAN_RHO for i in range(3))
TYPICAL: tuple[float, ...] = tuple(MEDIAN_RHO[i][i] for i in range(4))
HOLD_S = 1.0
WARM_UP_S = 1.0
WARM_DOWN_S = 5.0
SETTLE_S = 1.0
FREEZE_PROBABILITY = 0.05
#: Each member's turbulence-adaptation reference rho_0 (tempering above it only): 1.0 against each
#: member's own 99th percentile at its level (0.73, 0.79, 0.86, 1.82), tuning seeds: severe 389 false
#: declarations in 0.67 h and 33/36 failures against 705 and 28/36, the other levels alike.
ADAPT_REFERENCE: tuple[float, ...] = (1.0, 1.0, 1.0, 1.0)
#: Bumped whenever the members' design or the thresholds change (part of the cache key).
REVISION = 6
FORMAT = "f16mmae-turbulence-banks"
SET_FILE = "set.json"


class BankSetError(F16mmaeError):
    """A turbulence bank set cannot be found, designed or loaded; the message names the file."""


@dataclass(frozen=True)
class BankSet:
    """A loaded, checked set: the member banks (core.ModelBank, rising intensity) and the
    selector's settings (keyword arguments of core.TurbulenceBankSet), and the set's hash."""
    path: Path
    levels: tuple[str, ...]
    banks: tuple
    adapt_reference: tuple[float, ...]
    selector: dict
    set_hash: str


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _body_hash(body: dict) -> str:
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def set_path() -> Path:
    """Where the set is cached; its name carries a hash of the revision, the levels, the
    thresholds and the shipped tuned bank (which changes when the truth or the tuning does)."""
    with open(names_data_dir() / "nominal_tuned.f16bank", "rb") as f:
        header = f.read(52)
    spec = (f"{REVISION};{MEMBER_TUNING};{MEMBER_LEVELS};{BOUNDS};{TYPICAL};{HOLD_S};{WARM_UP_S};{WARM_DOWN_S};{SETTLE_S};"
            f"{FREEZE_PROBABILITY};{ADAPT_REFERENCE};{START};{START_STANDBY}")
    key = hashlib.sha256(spec.encode() + header[20:52]).hexdigest()[:16]
    base = os.environ.get("F16MMAE_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "f16mmae")
    return Path(base) / "banks" / f"turbulence_banks_{key}"


def names_data_dir() -> Path:
    from ..banks import DATA_DIR

    return DATA_DIR


def design_set(out_dir: str | Path, progress=None) -> Path:
    """Design the members and write the set into ``out_dir`` (created; written into a temporary
    sibling and renamed, so a half-written set is never found).  Returns ``out_dir``."""
    from .bank import NOMINAL_ALT_FT, NOMINAL_MACH, design_bank, write_bank
    from .model import linearize_truth
    from .tuning import load_tuning

    import dataclasses

    out_dir = Path(out_dir)
    ours = {SET_FILE} | {f"{level}.f16bank" for level in MEMBER_LEVELS}
    if out_dir.exists() and not {p.name for p in out_dir.iterdir()} <= ours:
        raise BankSetError(f"{out_dir} holds files that are not a turbulence bank set's; give a new or empty "
                           f"directory (nothing was written)")
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=out_dir.name + ".", dir=out_dir.parent))
    try:
        base = load_tuning(MEMBER_TUNING)
        lin = linearize_truth(NOMINAL_MACH, NOMINAL_ALT_FT, throttle=True)
        members = []
        for level in MEMBER_LEVELS:
            tuning = base if level == base.turbulence else dataclasses.replace(
                base, name=f"{base.name}-{level}", turbulence=level)
            design = design_bank(NOMINAL_MACH, NOMINAL_ALT_FT, tuning, linearized=lin, throttle_input=True)
            file = f"{level}.f16bank"
            bank = write_bank(design, tmp / file)
            members.append({"level": level, "file": file, "sha256": _sha256(tmp / file),
                            "content_hash": str(bank.content_hash), "tuning": tuning.name})
            if progress:
                progress(f"member {level}: {file}, content hash {bank.content_hash}")
        body = {"format": FORMAT, "revision": REVISION, "members": members, "start": START,
                "start_standby": START_STANDBY, "bounds": list(BOUNDS), "typical": list(TYPICAL), "hold_s": HOLD_S,
                "warm_up_s": WARM_UP_S, "warm_down_s": WARM_DOWN_S, "settle_s": SETTLE_S, "freeze_probability": FREEZE_PROBABILITY,
                "adapt_reference": list(ADAPT_REFERENCE)}
        (tmp / SET_FILE).write_text(json.dumps({**body, "set_hash": _body_hash(body)}, indent=1, sort_keys=True) + "\n")
        if out_dir.exists():
            shutil.rmtree(out_dir)
        tmp.rename(out_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out_dir


def load_set(directory: str | Path | None = None) -> BankSet:
    """The set in ``directory`` (default: :func:`set_path`, designed first if missing), checked:
    BankSetError naming the file and field for a missing file, a hash that does not match, or
    a field out of its range."""
    from ..banks import _load_bank_cached

    if directory is None:
        directory = set_path()
        if not (directory / SET_FILE).is_file():
            directory.parent.mkdir(parents=True, exist_ok=True)
            with open(directory.parent / (directory.name + ".lock"), "w") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)   # one process designs; the others wait and load it
                if not (directory / SET_FILE).is_file():
                    print(f"designing the turbulence bank set ({', '.join(MEMBER_LEVELS)}) into {directory} "
                          "(once; cached)...", file=sys.stderr, flush=True)
                    design_set(directory, progress=lambda line: print("  " + line, file=sys.stderr, flush=True))
    directory = Path(directory)
    manifest = directory / SET_FILE
    try:
        data = json.loads(manifest.read_text())
    except (OSError, ValueError) as exc:
        raise BankSetError(f"cannot read the turbulence bank set {manifest}: {exc}") from None

    def refuse(field: str, why: str):
        raise BankSetError(f"turbulence bank set {manifest}: {field} {why}")

    if not isinstance(data, dict) or data.get("format") != FORMAT:
        refuse("format", f"must be {FORMAT!r}")
    body = {k: v for k, v in data.items() if k != "set_hash"}
    if data.get("set_hash") != _body_hash(body):
        refuse("set_hash", "does not match the file's content (edited or damaged)")
    members = data.get("members")
    if not isinstance(members, list) or len(members) < 2:
        refuse("members", "must list at least 2 member banks")
    n = len(members)
    for key, count in (("bounds", n * (n - 1)), ("typical", n)):
        v = data.get(key)
        if not (isinstance(v, list) and len(v) == count and all(isinstance(x, (int, float)) and x > 0 for x in v)):
            refuse(key, f"must be {count} positive numbers")
    for key in ("hold_s", "warm_up_s", "warm_down_s", "settle_s", "freeze_probability"):
        if not isinstance(data.get(key), (int, float)):
            refuse(key, "must be a number")
    ref = data.get("adapt_reference")
    if not (isinstance(ref, list) and len(ref) == n and all(isinstance(x, (int, float)) and 0 <= x <= 100 for x in ref)):
        refuse("adapt_reference", f"must be {n} numbers in [0, 100]")
    start = data.get("start")
    if not (isinstance(start, int) and 0 <= start < n):
        refuse("start", f"must be a member index in [0, {n - 1}]")
    banks, levels = [], []
    for i, m in enumerate(members):
        if m.get("level") not in names.TURBULENCE_LEVELS:
            refuse(f"members[{i}].level", f"must be one of {', '.join(names.TURBULENCE_LEVELS)}")
        path = directory / str(m.get("file", ""))
        if not path.is_file() or path.parent != directory:
            refuse(f"members[{i}].file", f"{m.get('file')!r} is not a file of the set")
        if _sha256(path) != m.get("sha256"):
            refuse(f"members[{i}].sha256", f"does not match {path.name} (edited or damaged)")
        try:
            bank = _load_bank_cached(str(path))
        except (RuntimeError, ValueError) as exc:
            refuse(f"members[{i}].file", f"cannot be loaded: {exc}")
        if str(bank.content_hash) != m.get("content_hash"):
            refuse(f"members[{i}].content_hash", f"does not match {path.name}")
        banks.append(bank)
        levels.append(m["level"])
    if [names.TURBULENCE_LEVELS.index(x) for x in levels] != sorted(names.TURBULENCE_LEVELS.index(x) for x in set(levels)):
        refuse("members", "must be in rising turbulence level, each level once")
    selector = {"bounds": [float(x) for x in data["bounds"]], "typical": [float(x) for x in data["typical"]],
                "hold_s": float(data["hold_s"]), "warm_up_s": float(data["warm_up_s"]),
                "warm_down_s": float(data["warm_down_s"]), "settle_s": float(data["settle_s"]),
                "freeze_probability": float(data["freeze_probability"]), "start": start,
                "start_standby": int(data.get("start_standby", -1))}
    return BankSet(path=directory, levels=tuple(levels), banks=tuple(banks),
                   adapt_reference=tuple(float(x) for x in ref), selector=selector, set_hash=data["set_hash"])


def _start_member() -> Path:
    s = load_set()
    return s.path / f"{s.levels[s.selector['start']]}.f16bank"


def _register() -> None:
    from .. import banks

    banks.register_turbulence_set(load_set, _start_member)


_register()
