"""Where a soak's false declarations begin in the turbulence adaptation's scale s: re-fly each
flight of a soak's runs.jsonl that declared falsely (with the options it was given, refused if it does
not declare what its record says) and print, per false declaration, s at its
onset (the last frame before the declared hypothesis' probability passed 0.5), the least s over
the 3 s before, the mean over the 10 s before and the flight's median s (from 10 s on). With
--without KEY=VALUE the same flights fly again with that estimator setting (e.g.
adapt_floor_time_constant_s=0: the lull floor off, cpp/f16mmae/turbulence_adaptation.h) and the
declarations of both are printed; --figure FILE draws s and the declared hypothesis'
probability over the 40 s around each false declaration, with and without.
Example (docs/results/turbulence_adaptation.md, round 44):

    .venv/bin/python tools/soak/scale_at_onsets.py results/soakM8 --level moderate \\
        --without adapt_floor_time_constant_s=0 --figure docs/results/figures/lull_floor_round44.png
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.campaign.engine.drilldown import flies_as_recorded
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import NONE


def setting(text: str) -> tuple[str, object]:
    key, _, value = text.partition("=")
    if not key or not value:
        raise argparse.ArgumentTypeError(f"--without takes KEY=VALUE, got {text!r}")
    try:
        return key, float(value)
    except ValueError:
        return key, value


def onsets(result, rate_hz: float) -> list[tuple[str, int, int]]:
    """(hypothesis, onset frame, declaration frame) of each failure declaration of a flight."""
    hypotheses = list(result.hypotheses)
    p = np.nan_to_num(np.asarray(result.probabilities))
    out = []
    for d in result.declarations:
        if d["hypothesis"] == NONE or d["hypothesis"] not in hypotheses:
            continue
        k, i = hypotheses.index(d["hypothesis"]), int(round(d["time_s"] * rate_hz))
        j = min(i, len(p) - 1)
        while j > 0 and p[j, k] > 0.5:
            j -= 1
        out.append((d["hypothesis"], j, i))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("soak", help="a soak campaign's directory (its runs.jsonl)")
    ap.add_argument("--level", default="moderate", help="the turbulence level whose flights to read (default moderate)")
    ap.add_argument("--without", type=setting, action="append", default=[], metavar="KEY=VALUE",
                    help="fly the same flights again with this estimator setting changed (repeatable)")
    ap.add_argument("--figure", type=Path, help="write s and the declared probability around each declaration here")
    a = ap.parse_args(argv)
    runs_file = Path(a.soak) / "runs.jsonl"
    if not runs_file.is_file():
        ap.error(f"{runs_file} does not exist: give a soak campaign's output directory")
    if a.figure is not None and not a.figure.parent.is_dir():
        ap.error(f"--figure {a.figure}: the folder {a.figure.parent} does not exist")
    panels, banks = [], {}
    for line in runs_file.read_text().splitlines():
        r = json.loads(line)
        if r["scenario"]["turbulence"] != a.level or not r.get("false_declarations"):
            continue
        if r["bank"] not in banks:   # one load per bank the soak flew
            banks[r["bank"]] = load_bank(r["bank"])[2]
        bank = banks[r["bank"]]
        scenario = scenario_from_dict(r["scenario"])
        # the options the run was given, as its reproduce command flies them (the settings in force
        # of an older record name the bank's one p_min, which is not a scheduled bank's node floors)
        res = fly(scenario, bank, estimator_options=r["estimator"], record_probabilities=True)
        if not flies_as_recorded(r, res.declarations):
            raise SystemExit(f"scale_at_onsets: run {r['run_index']} (seed {r['seed']}) flown again does not declare "
                             "what its record says: not the code or bank that flew the soak")
        rate = 1.0 / res.frame_dt_s
        s = np.asarray(res.turbulence_scale)
        median = float(np.median(s[int(10 * rate):]))
        other = None
        if a.without:
            settings = {**r["estimator"], **dict(a.without)}
            other = fly(scenario, bank, estimator_options=settings, record_probabilities=True)
        for name, j, i in onsets(res, rate):
            before3, before10 = s[max(0, j - int(3 * rate)):j + 1], s[max(0, j - int(10 * rate)):j + 1]
            print(f"run {r['run_index']:3d} seed {r['seed']}: {name} declared at {i / rate:.2f} s; s at its onset "
                  f"({j / rate:.2f} s) {s[j]:.2f}, least over 3 s before {before3.min():.2f}, mean over 10 s "
                  f"{before10.mean():.2f}; the flight's median {median:.2f}")
            panels.append((r, name, j, i, res, other, rate))
        if other is not None:
            print(f"    with {' '.join(f'{k}={v}' for k, v in a.without)}: declarations "
                  f"{[(d['hypothesis'], round(d['time_s'], 2)) for d in other.declarations] or 'none'}")
    if a.figure is not None and panels:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(2, len(panels), figsize=(max(6.4, 4.2 * len(panels)), 5.2), squeeze=False,
                                 sharex="col")
        label = " ".join(f"{k}={v}" for k, v in a.without)
        for c, (r, name, j, i, res, other, rate) in enumerate(panels):
            lo, hi = max(0, i - int(30 * rate)), min(len(res.turbulence_scale), i + int(10 * rate))
            t = np.arange(lo, hi) / rate
            k = list(res.hypotheses).index(name)
            axes[0, c].plot(t, np.asarray(res.turbulence_scale)[lo:hi], label="as flown")
            axes[1, c].plot(t, np.nan_to_num(np.asarray(res.probabilities))[lo:hi, k], label="as flown")
            if other is not None:
                axes[0, c].plot(t, np.asarray(other.turbulence_scale)[lo:hi], label=label)
                axes[1, c].plot(t, np.nan_to_num(np.asarray(other.probabilities))[lo:hi, k], label=label)
            axes[0, c].set_title(f"run {r['run_index']}, {name} at {i / rate:.1f} s", fontsize=9)
            axes[0, c].set_ylabel("scale s")
            axes[1, c].set_ylabel(f"p({name})")
            axes[1, c].set_xlabel("time (s)")
            axes[0, c].legend(fontsize=7)
        fig.suptitle(f"{a.soak}: false declarations in {a.level} air", fontsize=10)
        fig.tight_layout()
        fig.savefig(a.figure, dpi=110)
        print(f"figure: {a.figure}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
