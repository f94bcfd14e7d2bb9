"""Flights that two campaigns of one command both plan, flown once.

``f16mmae campaign paper`` flies the envelope campaign and then the single-failure campaign: the
envelope's nominal point NOM is the single campaign's flight condition, with its cases, seeds,
bank and settings, so its 13 x N runs are the single campaign's runs.  Within
:func:`sharing`, ``runner.execute`` offers every record it stores (:func:`offer`) and, before
flying, takes the record of each spec that was already flown (:func:`take`) instead of flying
it again.  Outside the context both are no-ops.

A record is a pure function of its run function and its spec (``runner``), so a record is
reused only for the same function and an equal spec (every field, not only the run key: the
key leaves out e.g. the ``--tuning`` argument a record names).  A run function that labels the
record of another one declares it: ``fn.shares = (base, tags)`` says that ``fn(spec)`` is
``base(spec)`` with the spec's ``tags`` fields added, so the record without ``tags`` is
``base``'s record of the spec without ``tags`` (the envelope's ``run_point_spec`` is
``failure_runs.run_spec`` plus the ``point``).
``tests/python/test_campaign_paper.py`` checks the reused records equal the single command's.
"""
from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator

#: run key -> [(run function, spec, record)] while :func:`sharing` is active, else None.
_flown: dict[str, list[tuple[Callable, dict, dict]]] | None = None


@contextlib.contextmanager
def sharing() -> Iterator[None]:
    """Within: records offered by one ``execute`` are taken by the next (module docstring)."""
    global _flown
    if _flown is not None:  # nested: the outer context holds the records
        yield
        return
    _flown = {}
    try:
        yield
    finally:
        _flown = None


def _without(d: dict, tags: tuple[str, ...]) -> dict:
    return {k: v for k, v in d.items() if k not in tags}


def offer(run: Callable[[dict], dict], spec: dict, record: dict) -> None:
    """Keep ``record`` (what ``run(spec)`` returned) for a later :func:`take`, also as the
    record of ``run.shares``' base function."""
    if _flown is None:
        return
    entries = _flown.setdefault(spec["run_key"], [])
    entries.append((run, spec, record))
    shares = getattr(run, "shares", None)
    if shares is not None:
        base, tags = shares
        entries.append((base, _without(spec, tags), _without(record, tags)))


def take(run: Callable[[dict], dict], spec: dict) -> dict | None:
    """The record ``run(spec)`` returns, when an equal spec was flown by the same function
    within this context; else None."""
    if _flown is None:
        return None
    for fn, flown_spec, record in _flown.get(spec["run_key"], ()):
        if fn is run and flown_spec == spec:
            return record
    return None
