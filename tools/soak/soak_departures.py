"""Whether a soak's flights stay at their design condition: re-fly the flights of a soak's
runs.jsonl at one turbulence level with the truth's state recorded and print, per flight,
when it leaves the design altitude +- --band-ft, its lowest altitude and largest bank angle,
its first false declaration, and how many came before it left the band.  --feedback raw
flies the same seeds with the control law on the raw sensors (no estimator in the loop).
Example (docs/results/gust_states.md):

    .venv/bin/python tools/soak/soak_departures.py results/soak-1h-gust-adapt --level severe
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from f16mmae import core
from f16mmae.loop.flight import fly
from f16mmae.names import FEEDBACK_MODES, NONE
from f16mmae.truth import Scenario


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("soak", help="a soak campaign's directory (its runs.jsonl)")
    p.add_argument("--level", default="severe")
    p.add_argument("--band-ft", type=float, default=2000.0)
    p.add_argument("--feedback", default=None, choices=FEEDBACK_MODES, help="default: the soak's")
    a = p.parse_args()
    inside_s, before = 0.0, 0
    for line in (Path(a.soak) / "runs.jsonl").read_text().splitlines():
        r = json.loads(line)
        sc = r["scenario"]
        if sc["turbulence"] != a.level:
            continue
        bank = core.load_bank(r["bank"])
        scenario = Scenario(mach=sc["mach"], alt_ft=sc["alt_ft"], turbulence=sc["turbulence"],
                            duration_s=sc["duration_s"], seed=sc["seed"], feedback=a.feedback or sc["feedback"])
        f = fly(scenario, bank, record_series=True, record_probabilities=False, estimator_options=r["estimator"])
        log = f.series["truth_log"]
        state = log["state"]
        alt = state[:, log["state_names"].index("alt_ft")]
        phi = state[:, log["state_names"].index("phi_rad")]
        off = np.nonzero(np.abs(alt - sc["alt_ft"]) > a.band_ft)[0]
        leaves = off[0] / len(alt) * sc["duration_s"] if len(off) else None
        false = [d["time_s"] for d in f.declarations if d["hypothesis"] != NONE]
        n_before = sum(1 for t in false if leaves is None or t < leaves)
        inside_s += sc["duration_s"] if leaves is None else leaves
        before += n_before
        print(f"seed {sc['seed']}: leaves the band at {leaves if leaves is None else round(leaves, 1)} s, "
              f"lowest {alt.min():.0f} ft, largest bank {np.degrees(np.abs(phi).max()):.0f} deg, "
              f"first false declaration {false[0] if false else None} s, {n_before} of {len(false)} before "
              f"leaving", flush=True)
    print(f"{before} false declarations in {inside_s / 3600:.2f} h inside the band")


if __name__ == "__main__":
    main()
