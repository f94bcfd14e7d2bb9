"""``f16mmae bench``: the per-frame cost of the 13-filter MMAE bank, four ways, one run."""
from __future__ import annotations

import argparse
import json
import os
import platform
import sys

from .. import __version__
from ..bench.estimator import run_bench
from .options import CliError, number

DESCRIPTION = """\
Time one MMAE frame (13 steady-state filters: residuals, log-domain Bayes update with
the p_min floor, blended estimate, propagation) on an F-16-size synthetic bank (13
states, 5 inputs, 7 measurements; random stable Phi, DARE gains, each hypothesis with
its failed actuator column or sensor row removed), four ways, in one run:
  (a) the C++ loop alone (F16FilterBank.step, timed in C++)
  (b) the same bank called from Python, bank.step(z, u) once per frame
  (c) a numpy reference implementation (f16mmae.bench.estimator.NumpyMMAE)
  (d) filterpy's MMAEFilterBank on the same models (full Kalman filters; optional)
and print microseconds per frame with the ratios. Targets: (a) <= 1 us per frame,
(d)/(a) >= 3000. The numpy reference also cross-checks the C++ probabilities.
"""

EXAMPLES = """\
examples:
  f16mmae bench                       # a few seconds
  f16mmae bench --json bench.json     # the same numbers + machine info, as JSON
  f16mmae bench --frames 20000 --min-time 1.0
"""

TARGET_CPP_US = 1.0
TARGET_FILTERPY_RATIO = 3000.0


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "bench", help="per-frame cost of the estimator: C++, Python call, numpy, filterpy",
        description=DESCRIPTION, epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--frames", default="2000", metavar="N",
                   help="synthetic frames replayed by each timing (default 2000)")
    p.add_argument("--min-time", default="0.2", metavar="S",
                   help="seconds each timing runs at least; the fastest pass over the frames counts (default 0.2)")
    p.add_argument("--seed", default="1", metavar="N", help="seed of the synthetic bank and frames (default 1)")
    p.add_argument("--json", default=None, metavar="FILE", help="also write the numbers and machine info here")
    p.set_defaults(func=_run)


def machine_info() -> dict:
    """Where the numbers were measured."""
    import numpy

    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), cpu)
    except OSError:
        pass
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:
        cores = os.cpu_count()
    return {
        "cpu": cpu, "cores": cores, "platform": platform.platform(),
        "python": sys.version.split()[0], "numpy": numpy.__version__,
    }


def _run(args) -> int:
    frames = number("--frames", args.frames, integer=True, minimum=1)
    min_time_s = number("--min-time", args.min_time, minimum=0.0, below=3600.0)
    seed = number("--seed", args.seed, integer=True, minimum=1)
    result = run_bench(frames=frames, min_time_s=min_time_s, seed=seed)

    rows = [
        ("(a) C++ loop, F16FilterBank.step", result.cpp_loop_us),
        ("(b) Python call, bank.step(z, u)", result.python_call_us),
        ("(c) numpy reference", result.numpy_us),
        ("(d) filterpy MMAEFilterBank", result.filterpy_us),
    ]
    print(f"f16mmae bench: one MMAE frame, 13 filters x (13 states, 5 inputs, 7 measurements); "
          f"synthetic bank {result.bank_hash[:12]}, {frames} frames, f16mmae {__version__}")
    print(f"  {'implementation':36s} {'us/frame':>12s} {'frames/s':>12s}")
    for label, us in rows:
        if us is None:
            print(f"  {label:36s} {'-':>12s} {'-':>12s}")
        else:
            print(f"  {label:36s} {us:12.3f} {1e6 / us:12.0f}")
    ratios = result.ratios()
    if ratios:
        print("  ratios: " + ", ".join(f"{k} = {v:,.1f}x" for k, v in ratios.items()))
    if result.max_probability_difference is not None:
        print(f"  cross-check: max |p_numpy - p_C++| over {result.frames} frames = "
              f"{result.max_probability_difference:.1e}")
    targets = _targets(result)
    for name, t in targets.items():
        print(f"  target {name}: {'met' if t['met'] else 'NOT met'} ({t['measured']:,.3f} vs {t['target']:,})")
    for note in result.notes:
        print(f"  note: {note}")

    if args.json:
        record = {
            "f16mmae_version": __version__,
            "machine": machine_info(),
            "frames": frames, "min_time_s": min_time_s, "seed": seed,
            "bank_hash": result.bank_hash,
            "us_per_frame": {
                "cpp_loop": result.cpp_loop_us, "python_call": result.python_call_us,
                "numpy": result.numpy_us, "filterpy": result.filterpy_us,
            },
            "ratios": ratios,
            "max_probability_difference": result.max_probability_difference,
            "targets": targets,
            "notes": result.notes,
        }
        try:
            with open(args.json, "w", encoding="utf-8") as f:
                json.dump(record, f, indent=2)
                f.write("\n")
        except OSError as exc:
            raise CliError(f"--json {args.json!r}: {exc.strerror}") from None
        print(f"  written: {args.json}")
    return 0


def _targets(result) -> dict:
    out = {}
    if result.cpp_loop_us is not None:
        out["cpp_loop_us <= 1"] = {"target": TARGET_CPP_US, "measured": result.cpp_loop_us,
                                   "met": result.cpp_loop_us <= TARGET_CPP_US}
    ratio = result.ratios().get("filterpy / cpp_loop")
    if ratio is not None:
        out["filterpy / cpp_loop >= 3000"] = {"target": TARGET_FILTERPY_RATIO, "measured": ratio,
                                              "met": ratio >= TARGET_FILTERPY_RATIO}
    return out
