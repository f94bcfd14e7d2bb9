"""A single campaign's first declarations replayed through other level-0 banks, from one flight per run.

Each run of ``f16mmae campaign single --seed S --runs N --mode M`` (the same plan:
``failure_runs.plan``; ``--cases`` a subset) is flown once with the first bank of ``--banks`` and
the dwell 30 s (nothing is declared in an 8-s flight, so the flight does not depend on which
hypothesis the bank favours but through the blended estimate it feeds back, in which every
hypothesis on its floor weighs p_min), and its measurements z and commands u are kept.  Each
bank of ``--banks`` then replays them as one ``core.FilterBank`` of its 13 level-0 filters (its
p_min, the leading term stripped, as the estimator runs it), with the floor's fresh levels off
(the default) and/or on (``--fresh``; ``fresh_floor_levels``, cpp/f16mmae/filter_bank.h), and
its first declaration is the
first frame at which a failure hypothesis has held p_k > threshold for the bank's dwell
(``tools/cover/dwell_replay.py``'s rule, ``cpp/f16mmae/declarer.h``).  Scored per mode:

  FA            runs whose first declaration comes before the onset (NONE runs: at all),
  first right   failure runs whose first declaration after the onset names the injected failure,
  first wrong   failure runs whose first declaration after the onset names another failure,
  latency       of the first right declarations: median and p95 (s).

What follows a first declaration (level 1, back-outs) is not replayed.

Run: .venv/bin/python tools/cover/floor_levels.py --banks results/cover.f16bank,results/other.f16bank \
       --seed 7 --runs 10 --modes complete,stuck --cache results/floor7.npz
"""
from __future__ import annotations

import argparse
import os
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from f16mmae import core, names
from f16mmae.banks import load_bank

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dwell_replay import first_declaration, fly_undeclared, mode_runs  # noqa: E402

def _fly(args):
    res = fly_undeclared(*args, record_series=True)
    return res.series["z"].copy(), res.series["u"].copy()


def flights(bank_path: str, seed: int, runs: int, modes: list[str], cases: list[str] | None, workers: int):
    """[(mode, case, onset)], [(z, u)] of the plan's runs (NONE runs once, under mode "none")."""
    specs = mode_runs(bank_path, seed, runs, modes, cases)
    with ProcessPoolExecutor(workers) as pool:
        series = list(pool.map(_fly, [(bank_path, sc) for *_, sc in specs], chunksize=2))
    return [sp[:3] for sp in specs], series


def replay(bank, z: np.ndarray, u: np.ndarray, fresh: bool) -> np.ndarray:
    """(frames, 13) level-0 probabilities of ``bank`` over the flight's z, u."""
    models = [core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a, uninformative_width=h.uninformative_width,
                               uninformative_level_q=h.uninformative_level_q)
              for h in list(bank.hypotheses)[: names.K_BANK]]
    fb = core.FilterBank(models, p_min=float(bank.p_min), h_output=np.asarray(bank.h_output),
                         **({"fresh_floor_levels": True} if fresh else {}))
    return fb.step_frames(z - np.asarray(bank.z_trim), u[:, : bank.nu] - np.asarray(bank.u_trim))


def score(meta, probs, modes, threshold: float, dwell_frames: int, rate: float) -> tuple[dict, list[str]]:
    hyps = names.SINGLE_HYPOTHESES
    out, lines = {}, []
    frames = np.full(names.K_BANK, dwell_frames)
    for mode in ["none"] + modes:
        rows = [(c, t, p) for (m, c, t), p in zip(meta, probs) if m == mode]
        if not rows:
            continue
        fa = right = wrong = 0
        lat, notes = [], []
        for case, onset, p in rows:
            first = first_declaration(p, frames, threshold)
            t_first = None if first is None else first[0] / rate
            if first is not None and (onset is None or t_first < onset):
                fa += 1
                notes.append(f"FA:{case}>{hyps[first[1]]}@{t_first:.2f}")
                continue
            if onset is None or first is None:
                if onset is not None:
                    notes.append(f"miss:{case}")
                continue
            if hyps[first[1]] == case:
                right += 1
                lat.append(t_first - onset)
            else:
                wrong += 1
                notes.append(f"{case}>{hyps[first[1]]}")
        n_fail = sum(1 for r in rows if r[1] is not None)
        out[mode] = {"runs": len(rows), "fa": fa, "right": right, "wrong": wrong, "failures": n_fail, "latency": lat}
        lat_txt = f"latency median {np.median(lat):.2f} p95 {np.percentile(lat, 95):.2f} s" if lat else ""
        lines.append(f"  {mode:9s} runs {len(rows):3d}  FA {fa:2d}  first right {right}/{n_fail}  "
                     f"first wrong {wrong}  {lat_txt}  {' '.join(notes)}")
    return out, lines


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--banks", required=True, help="comma-separated bank files; the first one flies")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--modes", default="complete,stuck,hardover,null,loss=0.5")
    ap.add_argument("--cases", default=None, help="comma-separated cases (default: every case of each mode)")
    ap.add_argument("--fresh", default="off", help="fresh_floor_levels settings to replay: off, on, or off,on")
    ap.add_argument("--cache", required=True, help="npz of the flown z, u (flown once, then read)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--fly-only", action="store_true", help="fly and cache the runs, replay nothing")
    args = ap.parse_args(argv)
    modes = args.modes.split(",")
    banks = args.banks.split(",")
    if os.path.exists(args.cache):
        data = np.load(args.cache, allow_pickle=True)
        meta, series = [tuple(m) for m in data["meta"]], list(data["series"])
    else:
        meta, series = flights(banks[0], args.seed, args.runs, modes,
                               args.cases.split(",") if args.cases else None, args.workers)
        packed = np.empty(len(series), dtype=object)
        for i, zu in enumerate(series):
            packed[i] = zu
        np.savez_compressed(args.cache, meta=np.array(meta, dtype=object), series=packed)
    if args.fly_only:
        return
    for path in banks:
        _, _, bank = load_bank(path)
        threshold = float(bank.estimator_settings["threshold"])
        rate = float(bank.frame_rate_hz)
        dwell = max(1, int(round(float(bank.estimator_settings["dwell_s"]) * rate)))
        for fresh in args.fresh.split(","):
            probs = [replay(bank, z, u, fresh == "on") for z, u in series]
            res, lines = score(meta, probs, modes, threshold, dwell, rate)
            fa = sum(r["fa"] for r in res.values())
            right = sum(r["right"] for m, r in res.items() if m != "none")
            n = sum(r["failures"] for r in res.values())
            print(f"{path} fresh floor levels {fresh}: FA runs {fa}, first right {right}/{n}")
            print("\n".join(lines))


if __name__ == "__main__":
    main()
