"""The turbulence adaptation's scale s at each declaration of one hypothesis, over a campaign's
runs (the evidence behind a rough-air least dwell's scale: cpp/f16mmae/declarer.h).

Each run of DIR (a campaign output's runs.jsonl) that declares HYPOTHESIS, or fails it, is flown
again with its record's scenario and the options it was given on the scheduled bank (refused if it
does not declare what the record says), and s (the estimator's ``turbulence_scale``, from its own
residuals) is read on the frame of each declaration. Prints a line per run (turbulence, case, run,
the declarations with s), then per turbulence level the summary over the failure runs' first
declaration of HYPOTHESIS (median, p99, largest) and the range over the false ones (runs whose case
is another).

    python tools/latency/scale_at_declarations.py DIR [--hypothesis RUD]
"""
from __future__ import annotations

import argparse
import collections
import json
import sys
from pathlib import Path

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.campaign.engine.drilldown import flies_as_recorded
from f16mmae.loop.flight import fly, scenario_from_dict


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("dir", help="a campaign output directory (its runs.jsonl)")
    p.add_argument("--hypothesis", default="RUD", help="the hypothesis whose declarations are read (default RUD)")
    args = p.parse_args(argv)
    records = Path(args.dir) / "runs.jsonl"
    if not records.is_file():
        p.error(f"{records}: no such file (DIR must be a campaign output)")
    bank = load_bank("scheduled")[2]
    rate = float(bank.frame_rate_hz)
    failed, false = collections.defaultdict(list), collections.defaultdict(list)
    for line in records.read_text().splitlines():
        r = json.loads(line)
        h = args.hypothesis
        if r["case"] != h and not any(d["hypothesis"] == h for d in r["declarations"]):
            continue
        # the whole flight in one call; the flight records s after each frame (FlightResult.turbulence_scale)
        # the options the run was given, as its reproduce command flies them
        result = fly(scenario_from_dict(r["scenario"]), bank, estimator_options=r["estimator"],
                     record_probabilities=True)
        if not flies_as_recorded(r, result.declarations):
            sys.exit(f"scale_at_declarations: {r['case']} run {r['run_index']} ({r['scenario'].get('turbulence')}) "
                     "flown again does not declare what its record says: not the code or bank that flew it")
        s = result.turbulence_scale
        at = [(d["hypothesis"], d["time_s"], float(s[min(int(round(d["time_s"] * rate)), len(s) - 1)]))
              for d in result.declarations]
        level = r["scenario"].get("turbulence")
        print(level, r["case"], r["run_index"], " ".join(f"{n}@{t:.2f} s={v:.1f}" for n, t, v in at), flush=True)
        mine = [v for n, _, v in at if n == h]
        if mine:
            (failed if r["case"] == h else false)[level].append(mine[0] if r["case"] == h else mine)
    for level in sorted(set(failed) | set(false)):
        if failed[level]:
            v = np.array(failed[level])
            print(f"{level}: {len(v)} failed-{args.hypothesis} runs, s at the declaration median {np.median(v):.1f}, "
                  f"p99 {np.percentile(v, 99):.1f}, largest {v.max():.1f}")
        if false[level]:
            v = np.concatenate([np.array(x) for x in false[level]])
            print(f"{level}: {len(v)} false {args.hypothesis} declarations, s {v.min():.1f}-{v.max():.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
