"""Model banks: locate a shipped tuning or a bank file, load it once per process, read the
estimator settings it recommends.

A bank is named on the command line as ``tuned`` / ``untuned`` (the nominal banks shipped in
``data/``, designed at Mach 0.4, 20,000 ft), as ``scheduled`` (banks designed on the grid
``names.SCHEDULE_GRID``, one scheduled-bank file generated on first use into the cache:
``$F16MMAE_CACHE_DIR`` or ``~/.cache/f16mmae``, ``banks/``) or as the path of a bank file
written by ``f16mmae design`` (``--schedule`` too).  Loading goes through the C++ loader
(``core.load_bank``), which checks the file (hash, shapes, finiteness, covariances); a file that
fails is a :class:`BankError` naming the file and the reason.
"""
from __future__ import annotations

import functools
import hashlib
from pathlib import Path
from typing import Callable

from . import core
from .cache import cache_root
from .errors import F16mmaeError
from .names import (SCHEDULE_DESIGN_REVISION, SCHEDULE_FAILED_SENSOR_NOISE, SCHEDULE_FAILURE_MODEL, SCHEDULE_GRID,
                    SCHEDULE_GUST_NODE_CHOICE, SCHEDULE_GUST_STATES_BELOW_FT, SCHEDULE_NODE_TUNING,
                    SCHEDULE_THROTTLE_INPUT, SCHEDULED_BANK, SHIPPED_TUNINGS, TURBULENCE_BANK)

#: Where the shipped nominal banks live.
DATA_DIR = Path(__file__).resolve().parent / "data"


class BankError(F16mmaeError):
    """A bank cannot be found or loaded; the message names the file and why."""


#: Writes the scheduled bank to a path (registered by f16mmae.design.schedule, a layer above).
_schedule_generator: Callable[[Path], None] | None = None


def register_schedule_generator(generate: Callable[[Path], None]) -> None:
    """``generate(path)`` designs the ``scheduled`` bank into ``path`` when it is missing."""
    global _schedule_generator
    _schedule_generator = generate


#: The turbulence bank set (design/turbulence_banks.py, a layer above, registers it): its
#: loader (the checked set, designed first if missing) and its start member: (the set file's
#: path, the member's core.ModelBank).
_turbulence_set: tuple[Callable[[], object], Callable[[], tuple]] | None = None


def register_turbulence_set(load: Callable[[], object], start_member: Callable[[], tuple]) -> None:
    global _turbulence_set
    _turbulence_set = (load, start_member)


def turbulence_bank_set():
    """The turbulence bank set (``design.turbulence_banks.BankSet``); BankError if no layer
    above registered it (import ``f16mmae.design.turbulence_banks``)."""
    if _turbulence_set is None:
        raise BankError(f"the {TURBULENCE_BANK!r} bank set is not available: import f16mmae.design.turbulence_banks")
    return _turbulence_set[0]()


def scheduled_bank_path() -> Path:
    """Where the ``scheduled`` bank is cached. Its name carries a hash of the grid, the node tuning, the
    design's revision, its failure model and failed sensors' noise, its gust-state nodes and their choice, its throttle input, and of the shipped
    tuned bank (which changes whenever the truth model or the tuning is re-calibrated), so a stale
    schedule is never picked up."""
    nominal = DATA_DIR / "nominal_tuned.f16bank"
    with open(nominal, "rb") as f:
        header = f.read(52)  # magic, version, size, SHA-256 of the payload
    key = hashlib.sha256(f"{SCHEDULE_GRID};{SCHEDULE_NODE_TUNING};{SCHEDULE_DESIGN_REVISION};{SCHEDULE_FAILURE_MODEL};"
                         f"{SCHEDULE_FAILED_SENSOR_NOISE};"
                         f"{SCHEDULE_GUST_STATES_BELOW_FT:g};{SCHEDULE_GUST_NODE_CHOICE};{SCHEDULE_THROTTLE_INPUT}".encode()
                         + header[20:52]).hexdigest()[:16]
    return cache_root() / "banks" / f"scheduled_tuned_{key}.f16sched"


def bank_path(tuning: str) -> Path:
    """The bank file for ``tuned`` / ``untuned`` (shipped nominal banks), ``scheduled`` (the
    cached scheduled bank, designed first if missing and a generator is registered) or a FILE
    path."""
    if tuning in SHIPPED_TUNINGS:
        return DATA_DIR / f"nominal_{tuning}.f16bank"
    if tuning == SCHEDULED_BANK:
        path = scheduled_bank_path()
        if not path.is_file() and _schedule_generator is not None:
            _schedule_generator(path)
        return path
    if tuning == TURBULENCE_BANK:
        turbulence_bank_set()   # BankError if unavailable
        return _turbulence_set[1]()[0]   # the set file
    p = Path(tuning)
    if not p.is_file():
        raise BankError(
            f"{tuning!r} is neither a shipped tuning ({', '.join(SHIPPED_TUNINGS)}), "
            f"nor {SCHEDULED_BANK!r}, nor {TURBULENCE_BANK!r}, nor a readable bank file"
        )
    return p.resolve()


@functools.lru_cache(maxsize=8)
def _load_bank_cached(path: str):
    return core.load_bank(path)


def load_bank(tuning: str):
    """(label, path, ModelBank) of a tuning name or bank file; BankError if unreadable.
    ``turbulence``: the set file's path and its start member (flown alone, or as the set with
    ``turbulence_banks``)."""
    if tuning == TURBULENCE_BANK:
        turbulence_bank_set()   # BankError if unavailable
        path, bank = _turbulence_set[1]()
        return TURBULENCE_BANK, path, bank
    path = bank_path(tuning)
    if not path.is_file():
        build = (f"f16mmae design --schedule --failure-model {SCHEDULE_FAILURE_MODEL} --failed-sensor-noise "
                 f"{SCHEDULE_FAILED_SENSOR_NOISE} --gust-states-below-ft "
                 f"{SCHEDULE_GUST_STATES_BELOW_FT:g} --gust-node-choice {SCHEDULE_GUST_NODE_CHOICE}"
                 f"{' --throttle-input' if SCHEDULE_THROTTLE_INPUT else ' --no-throttle-input'} --out {path}"
                 if tuning == SCHEDULED_BANK else
                 f"f16mmae design --mach 0.4 --alt-ft 20000 --tuning {tuning} --out {path}")
        raise BankError(f"the {tuning!r} bank {path} is missing; build it with '{build}'")
    try:
        bank = _load_bank_cached(str(path))
    except (RuntimeError, ValueError) as exc:
        raise BankError(f"cannot load bank {path}: {exc}") from None
    label = tuning if tuning in SHIPPED_TUNINGS + (SCHEDULED_BANK, TURBULENCE_BANK) else (bank.tuning or path.stem)
    return label, path, bank


def bank_estimator_settings(model_bank, options: dict | None = None) -> dict:
    """The estimator settings a bank's design recommends: the typed fields ``p_min``,
    ``threshold`` and ``dwell_s`` of the bank file (since format version 2, range-checked by the
    one C++ loader) and, where the bank recommends one, ``dwell_nats_per_hypothesis`` (name ->
    N_k, the hypotheses' ``dwell_nats`` fields > 0, format version 4); then ``options`` over
    them (which win). An option ``dwell_nats`` without ``dwell_nats_per_hypothesis`` overrides
    the bank's table too (the one evidence dwell it names for every hypothesis). mmae-daemon
    applies the same rule to its flags (``--dwell-nats``, ``--dwell-nats-per-hypothesis``)."""
    settings = dict(model_bank.estimator_settings)
    options = dict(options or {})
    if "dwell_nats" in options and "dwell_nats_per_hypothesis" not in options:
        settings.pop("dwell_nats_per_hypothesis", None)
    return {**settings, **options}
