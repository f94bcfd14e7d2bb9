"""The runs that went wrong, each with the one command that flies it again.

A run is *not clean* when its outcome is not ``correct`` (missed or wrong), or it had a false
alarm, or it was transient-wrong (``outcomes.transient_wrong``).  :func:`not_clean` lists them
in the campaign's plan order with their seed, outcome, flags, final hypothesis, declarations
and :func:`reproduce_command`.

``reproduce_command(scenario, bank, estimator, dither_scale)`` writes the ``f16mmae run``
command line whose flight is the run's: every scenario field the run command sets (seed,
duration, turbulence, Mach and altitude as exact decimal reprs, feedback, dither on/off and
scale, each failure as ``--fail NAME@TIME:MODE[=VALUE]`` in the record's order, each maneuver
as ``--maneuver``), the bank
(``tuned`` / ``untuned`` or a bank file) and every estimator override.  The flight it gives
is the record's scenario and the record's declarations (tests/python/test_campaign_drilldown.py
flies one run of each campaign kind both ways).
"""
from __future__ import annotations

import shlex
from collections.abc import Callable, Iterable

from ...loop.estimator_options import command_line_flags

FLAGS: tuple[str, ...] = ("false_alarm", "transient_wrong")


def is_clean(record: dict) -> bool:
    return record["outcome"] == "correct" and not any(record.get(f) for f in FLAGS)


def reproduce_command(scenario: dict, bank: str, estimator: dict, dither_scale: float = 1.0) -> str:
    """The ``f16mmae run`` command of one run (module docstring)."""
    args = ["f16mmae", "run", "--seed", str(scenario["seed"]), "--duration", repr(float(scenario["duration_s"])),
            "--turbulence", scenario["turbulence"], "--mach", repr(float(scenario["mach"])),
            "--alt-ft", repr(float(scenario["alt_ft"])), "--feedback", scenario["feedback"]]
    dither = scenario.get("dither") or {}
    if not dither.get("enabled", True):
        args.append("--no-dither")
    elif dither_scale != 1.0:
        args += ["--dither-scale", repr(float(dither_scale))]
    for f in scenario.get("failures", ()):
        text = f"{f['name']}@{float(f['time_s'])!r}:{f['mode']}"
        if f.get("value") is not None:
            text += f"={float(f['value'])!r}"
        args += ["--fail", text]
    burst = scenario.get("gust_burst")
    if burst:
        args += ["--gust-burst", f"{burst['level']}@{float(burst['start_s'])!r}+{float(burst['duration_s'])!r}"]
    for m in scenario.get("maneuvers", ()):
        args += ["--maneuver", m]
    args += ["--bank", str(bank)]
    args += command_line_flags(estimator)
    return shlex.join(args)


def record_command(record: dict, dither_scale: float = 1.0) -> str:
    """:func:`reproduce_command` of a stored run record (its scenario, bank and overrides)."""
    return reproduce_command(record["scenario"], record.get("bank", record["tuning"]), record["estimator"],
                             dither_scale)


def flies_as_recorded(record: dict, declarations: Iterable[dict]) -> bool:
    """Whether a run flown again (its record's scenario, bank and ``estimator``, the options it was
    given, as :func:`record_command` flies them) declared what the record says: every declaration's
    hypothesis and time, in order. A lab tool that reads a flown-again run refuses one that does not."""
    def key(ds):
        return [(d["hypothesis"], round(float(d["time_s"]), 6)) for d in ds]
    return key(record.get("declarations") or []) == key(declarations)


def not_clean(records: Iterable[dict], command: Callable[[dict], str], label: Callable[[dict], dict]) -> list[dict]:
    """Every run that was not clean: ``label(record)`` (the fields naming its case), then
    ``seed``, ``run_index``, ``outcome``, ``flags``, ``final_hypothesis``, ``declarations``
    and ``command`` (``command(record)``)."""
    out = []
    for r in records:
        if is_clean(r):
            continue
        out.append({**label(r), "run_index": r["run_index"], "seed": r["seed"], "outcome": r["outcome"],
                    "flags": [f for f in FLAGS if r.get(f)], "final_hypothesis": r["final_hypothesis"],
                    "declarations": r["declarations"], "command": command(r)})
    return out
