"""``f16mmae bench estimator|truth|lcm``: the benchmarks, one front end.

* ``estimator`` -- the per-frame cost of the 13-filter MMAE bank, four ways, one run
  (:mod:`f16mmae.bench.estimator`);
* ``truth``     -- the truth model against bare JSBSim, and the closed loop against the truth
  alone (:mod:`f16mmae.bench.truth`);
* ``lcm``       -- the round trip to ``mmae-daemon`` over LCM against a C++ echo
  (``tools/latency/lcm_latency.py`` of a source checkout, with the latency tools built
  beside it and never installed; its options follow ``lcm``).
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path

from ..banks import BankError, load_bank
from ..bench import estimator, scheduled, truth
from ..names import TURBULENCE_LEVELS
from ..outputs import writable_file
from ..truth.aircraft import ALT_FT_RANGE, MACH_RANGE
from .options import CliError, add_estimator_arguments, estimator_options_from_args, number

DESCRIPTION = __doc__.split("\n\n", 1)[1]

ESTIMATOR_DESCRIPTION = """\
Time one MMAE frame (13 steady-state filters: residuals, log-domain Bayes update with
the p_min floor, blended estimate, propagation) on an F-16-size synthetic bank (13
states, 5 inputs, 7 measurements; random stable Phi, DARE gains, each hypothesis with
its failed actuator column or sensor row removed), four ways, in one run:
  (a) the C++ loop alone (F16FilterBank.step, timed in C++); (a') the same with the
      turbulence adaptation on (cpp/f16mmae/turbulence_adaptation.h)
  (b) the same bank called from Python, bank.step(z, u) once per frame
  (c) a numpy reference implementation (f16mmae.bench.estimator.NumpyMMAE)
  (d) filterpy's MMAEFilterBank on the same models (full Kalman filters; optional)
and print microseconds per frame with the ratios. Targets: (a) <= 1 us per frame,
(d)/(a) >= 3000. The numpy reference also cross-checks the C++ probabilities.
Then the hierarchical bank's frame in the C++ loop, unscheduled and scheduled on air data
(interpolate, nearest; f16mmae.bench.scheduled), with the ratios; target <= 2 us scheduled.
"""

ESTIMATOR_EXAMPLES = """\
examples:
  f16mmae bench estimator                       # a few seconds
  f16mmae bench estimator --json bench.json     # the same numbers + machine info, as JSON
  f16mmae bench estimator --frames 20000 --min-time 1.0
"""

TRUTH_DESCRIPTION = """\
The truth model's cost, measured in one process with the timings interleaved (the
machine's load changes; ratios inside one run are what to compare): bare JSBSim stepping
of the stock F-16 and of our derived aircraft against whole truth-model flights (FCS,
actuators, sensors, dither) on the C++ and the Python engine, set-up from the per-condition
pool included, and the first flight of a condition (load and trim); the closed loop (the
--bank in the loop with the estimator options given, probabilities recorded) against the
truth alone; the dither's peak response at the nominal point; then flights per second of a
single-failure campaign (13 cases x --campaign-runs) on a process pool over all cores.

  f16mmae bench truth --repeat 21                        # the tuned bank (goal <= 1.1)
  f16mmae bench truth --campaign-runs 0 --bank scheduled --adapt-turbulence \\
      --trim-tracking 30 --mach 0.45 --alt-ft 22500      # scheduled, off-grid (goal <= 1.3)
"""


def register(subparsers) -> None:
    p = subparsers.add_parser("bench", help="benchmarks: estimator, truth model, LCM round trip",
                              description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    kinds = p.add_subparsers(dest="bench", metavar="BENCH")
    e = kinds.add_parser("estimator", help="per-frame cost of the estimator: C++, Python call, numpy, filterpy",
                         description=ESTIMATOR_DESCRIPTION, epilog=ESTIMATOR_EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    e.add_argument("--frames", default="2000", metavar="N",
                   help="synthetic frames replayed by each timing (default 2000)")
    e.add_argument("--min-time", default="0.2", metavar="S",
                   help="seconds each timing runs at least; the fastest pass over the frames counts (default 0.2)")
    e.add_argument("--seed", default="1", metavar="N", help="seed of the synthetic bank and frames (default 1)")
    e.add_argument("--json", default=None, metavar="FILE", help="also write the numbers and machine info here")
    e.set_defaults(func=_estimator)
    t = kinds.add_parser("truth", help="truth model against bare JSBSim; closed loop against the truth",
                         description=TRUTH_DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    t.add_argument("--duration-s", default="8", metavar="S", help="simulated flight per timing (default 8 s)")
    t.add_argument("--repeat", default="5", metavar="N", help="timings of each, the best counts (default 5)")
    t.add_argument("--campaign-runs", default="10", metavar="N",
                   help="runs per case of the campaign timed on all cores: 13 x N flights (default 10; 0: none)")
    t.add_argument("--bank", default="tuned", metavar="tuned|untuned|scheduled|FILE",
                   help="the bank of the closed-loop timing (default tuned)")
    t.add_argument("--mach", default=None, metavar="M", help="Mach of the closed-loop timing (default: the bank's)")
    t.add_argument("--alt-ft", default=None, metavar="H", help="altitude of the closed-loop timing, ft (default: the bank's)")
    add_estimator_arguments(t)
    t.set_defaults(func=_truth)
    n = kinds.add_parser("lcm", help="LCM round trip to mmae-daemon against a C++ echo", add_help=False,
                         description="the LCM latency benchmark; 'f16mmae bench lcm --help' lists its options")
    n.set_defaults(func=_lcm, passes_on_arguments=True)
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])


def _estimator(args) -> int:
    frames = number("--frames", args.frames, integer=True, minimum=1, below=10**7)
    min_time_s = number("--min-time", args.min_time, minimum=0.0, below=3600.0)
    seed = number("--seed", args.seed, integer=True, minimum=1, below=2**31)
    if args.json:
        writable_file(args.json, "--json")
    result = estimator.run_bench(frames=frames, min_time_s=min_time_s, seed=seed)
    record = estimator.report(result, sys.stdout)
    record["scheduled"] = scheduled.report(
        scheduled.run_scheduled_bench(frames=frames, min_time_s=min_time_s, seed=seed), sys.stdout)
    if args.json:
        record.update(min_time_s=min_time_s, seed=seed)
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(record, f, indent=2)
            f.write("\n")
        print(f"  written: {args.json}")
    return 0


def _truth(args) -> int:
    duration_s = number("--duration-s", args.duration_s, minimum=0.0, exclusive=True, below=3600.0)
    repeat = number("--repeat", args.repeat, integer=True, minimum=1, below=1000)
    runs = number("--campaign-runs", args.campaign_runs, integer=True, minimum=0, below=1001)
    mach = None if args.mach is None else number("--mach", args.mach, minimum=MACH_RANGE[0], maximum=MACH_RANGE[1])
    alt_ft = (None if args.alt_ft is None
              else number("--alt-ft", args.alt_ft, minimum=ALT_FT_RANGE[0], maximum=ALT_FT_RANGE[1]))
    options = estimator_options_from_args(args)
    try:
        load_bank(args.bank)  # a bad bank is named before the timings, not after
    except BankError as exc:
        raise CliError(f"--bank: {exc}") from None
    r = truth.benchmark(duration_s, repeat)
    overhead = truth.closed_loop_overhead(duration_s, repeat, args.bank, mach, alt_ft, **options)
    truth.report(r, truth.dither_levels(), overhead, sys.stdout)
    truth.report_dither_in_turbulence({lv: truth.dither_in_turbulence(lv) for lv in TURBULENCE_LEVELS}, sys.stdout)
    if runs:
        _campaign_rate(runs)
    return 0


def _campaign_rate(runs: int) -> None:
    """Fly the single-failure campaign (13 cases x ``runs``, 8-s flights, light turbulence) on a
    process pool over all cores into a temporary folder; print flights per second."""
    import tempfile

    from ..campaign.engine.executor import default_workers, make_executor
    from ..campaign.single import SingleCampaign, run_campaign

    cfg = SingleCampaign(runs=runs, baseline=None)
    workers = default_workers()
    with tempfile.TemporaryDirectory() as out, make_executor(workers) as ex:
        outcome = run_campaign(cfg, out, ex, show_progress=False, measure_cost=False)
    t = outcome.summary["timing"]
    n = t["runs_executed"]
    print(f"single-failure campaign, {n} flights of {cfg.duration_s:g} s on {workers} workers: "
          f"{t['wall_s']:.2f} s wall, {n / t['wall_s']:.1f} flights/s "
          f"(per flight: truth {1e3 * t['run_truth_s_sum'] / n:.2f} ms, estimator "
          f"{1e3 * t['run_estimator_s_sum'] / n:.2f} ms)")


#: The LCM latency driver in a source checkout (python/harness/f16mmae/cli -> the checkout).
LCM_LATENCY = Path(__file__).resolve().parents[4] / "tools" / "latency" / "lcm_latency.py"


def _lcm(args) -> int:
    if not LCM_LATENCY.is_file():
        raise CliError(f"f16mmae bench lcm runs from a source checkout: {LCM_LATENCY} is not there (the "
                       f"LCM latency benchmark and its tools, tools/latency/, are never installed); "
                       f"clone the repository and run 'make build' there")
    spec = importlib.util.spec_from_file_location("lcm_latency", LCM_LATENCY)
    driver = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(driver)
    return driver.main(args.passed_on)
