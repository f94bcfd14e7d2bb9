"""Model banks: locate a shipped tuning or a bank file, load it once per process, read the
estimator settings it recommends.

A bank is named on the command line as ``tuned`` / ``untuned`` (the nominal banks shipped in
``data/``, designed at Mach 0.4, 20,000 ft) or as the path of a bank file written by
``f16mmae design``.  Loading goes through the C++ loader (``core.load_bank``), which checks
the file (hash, shapes, finiteness, covariances); a file that fails is a :class:`BankError`
naming the file and the reason.
"""
from __future__ import annotations

import functools
from pathlib import Path

from . import core
from .errors import F16mmaeError
from .names import SHIPPED_TUNINGS

#: Where the shipped nominal banks live.
DATA_DIR = Path(__file__).resolve().parent / "data"


class BankError(F16mmaeError):
    """A bank cannot be found or loaded; the message names the file and why."""


def bank_path(tuning: str) -> Path:
    """The bank file for ``tuned`` / ``untuned`` (shipped nominal banks) or a FILE path."""
    if tuning in SHIPPED_TUNINGS:
        return DATA_DIR / f"nominal_{tuning}.f16bank"
    p = Path(tuning)
    if not p.is_file():
        raise BankError(
            f"{tuning!r} is neither a shipped tuning ({', '.join(SHIPPED_TUNINGS)}) "
            f"nor a readable bank file"
        )
    return p.resolve()


@functools.lru_cache(maxsize=8)
def _load_bank_cached(path: str):
    return core.load_bank(path)


def load_bank(tuning: str):
    """(label, path, ModelBank) of a tuning name or bank file; BankError if unreadable."""
    path = bank_path(tuning)
    if not path.is_file():
        raise BankError(
            f"the shipped {tuning!r} bank {path} is missing; build it with "
            f"'f16mmae design --mach 0.4 --alt-ft 20000 --tuning {tuning} --out {path}'"
        )
    try:
        bank = _load_bank_cached(str(path))
    except (RuntimeError, ValueError) as exc:
        raise BankError(f"cannot load bank {path}: {exc}") from None
    label = tuning if tuning in SHIPPED_TUNINGS else (bank.tuning or path.stem)
    return label, path, bank


def bank_estimator_settings(model_bank) -> dict:
    """The estimator settings a bank's design recommends: the typed fields ``p_min``,
    ``threshold`` and ``dwell_s`` of the bank file (since format version 2, range-checked by the
    one C++ loader); mmae-daemon applies the same fields."""
    return dict(model_bank.estimator_settings)
