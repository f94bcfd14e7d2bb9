"""A single campaign's first declarations under other dwells, exactly, from one flight per run.

Up to its first declaration a run does not depend on the dwell: the declarer acts only through
its declarations (design/dwell.py).  So each run of ``f16mmae campaign single --seed S --runs N
--mode M`` (the same plan: ``failure_runs.plan``) is flown once with the bank's settings but
the dwell 30 s (nothing is declared in an 8-s flight, the bank stays at level 0) and its 13
level-0 probabilities recorded; for any dwell rule the first declaration is then the first
frame at which some failure hypothesis k has held p_k > threshold on dwell_k consecutive frames
(``cpp/f16mmae/declarer.h``, one hypothesis above a threshold > 0.5 at a time) -- the same frame
and hypothesis the closed loop would have declared.  What follows a declaration (level 1, back-
outs) is not replayed: this scores the first declaration only --

  FA runs       runs whose first declaration comes before the onset (or, without a failure, at all),
  first right   failure runs whose first declaration after the onset names the injected failure,
  first wrong   failure runs whose first declaration after the onset names another failure,
  latency       of the first right declarations: median and p95 (s).

Rules (``--rules``, ``;``-separated): ``D`` one dwell (s) for every hypothesis, or
``D,NAME=D2,NAME=D3`` a default and per-hypothesis dwells, optionally with ``fast=S@X``: an
evidence-scaled dwell, k declared already after S seconds above the threshold once its
log-odds ln(p_k / sum_{j != k} p_j) reach X nats.  The probabilities are cached in
``--cache`` (npz), so rules can be tried again without flying.

Run: .venv/bin/python tools/cover/dwell_replay.py --bank results/cover.f16bank --seed 7 --runs 10 \
       --modes complete,stuck,hardover,null,loss=0.5 --rules "0.5;0.25;0.5,LF=0.5,RF=0.5" --cache results/replay7.npz
"""
from __future__ import annotations

import argparse
import dataclasses
import os
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from f16mmae import names
from f16mmae.banks import load_bank
from f16mmae.campaign.engine.failure_runs import plan
from f16mmae.campaign.single.campaign import SingleCampaign, mode_cases
from f16mmae.loop.flight import fly, scenario_from_dict

MEASURE_DWELL_S = 30.0
_BANK = {}


def fly_undeclared(bank_path: str, scenario: dict, **record):
    """The flight of ``scenario`` with ``bank_path``'s bank and a dwell (MEASURE_DWELL_S) no
    flight reaches, so that what it records is the level-0 bank's alone; ``record``: fly's
    record_* keywords."""
    if bank_path not in _BANK:
        _BANK[bank_path] = load_bank(bank_path)[2]
    res = fly(scenario_from_dict(scenario), _BANK[bank_path], estimator_options={"dwell_s": MEASURE_DWELL_S},
              **record)
    if res.declarations:
        raise RuntimeError(f"a declaration with a {MEASURE_DWELL_S} s dwell: {res.declarations}")
    return res


def _fly(args):
    res = fly_undeclared(*args, record_probabilities=True)
    cols = [res.hypotheses.index(h) for h in names.SINGLE_HYPOTHESES]
    return res.probabilities[:, cols].astype(np.float32)


def mode_runs(bank_path: str, seed: int, runs: int, modes: list[str], cases: list[str] | None = None):
    """[(mode, case, onset, scenario)] of the single campaign's plan in each mode (NONE runs once,
    under mode "none"; ``cases`` keeps only those)."""
    specs = []
    label, _, bank = load_bank(bank_path)
    for mode in modes:
        cfg = mode_cases(SingleCampaign(runs=runs, seed=seed, tuning=bank_path, baseline=None, mode=mode))[0]
        keep = [c for c in cfg.cases if (cases is None or c in cases) and (c != names.NONE or mode == modes[0])]
        cfg = dataclasses.replace(cfg, cases=tuple(keep))
        for s in plan(cfg, {label: (bank_path, bank)}):
            onset = s["scenario"]["failures"][0]["time_s"] if s["scenario"]["failures"] else None
            specs.append((mode if s["case"] != names.NONE else "none", s["case"], onset, s["scenario"]))
    return specs


def flights(bank_path: str, seed: int, runs: int, modes: list[str], workers: int):
    specs = mode_runs(bank_path, seed, runs, modes)
    with ProcessPoolExecutor(workers) as pool:
        probs = list(pool.map(_fly, [(bank_path, sc) for *_, sc in specs], chunksize=4))
    return [sp[:3] for sp in specs], probs


def parse_rule(text: str) -> tuple[np.ndarray, float | None, float]:
    """(dwell per hypothesis (s), fast dwell (s) or None, its log-odds X)."""
    parts = text.split(",")
    d = np.full(names.K_BANK, float(parts[0]))
    fast, x = None, np.inf
    for p in parts[1:]:
        k, v = p.split("=")
        if k == "fast":
            fast, x = (float(y) for y in v.split("@"))
        else:
            d[names.SINGLE_HYPOTHESES.index(k)] = float(v)
    return d, fast, x


def first_declaration(p: np.ndarray, dwell_frames: np.ndarray, threshold: float, fast_frames: int | None = None,
                      log_odds: float = np.inf) -> tuple[int, int] | None:
    """(frame, k) of the first declaration (p: frames x 13), or None."""
    count, cand = 0, -1
    for i in range(len(p)):
        above = np.flatnonzero(p[i, 1:] > threshold)
        if not len(above):
            count, cand = 0, -1
            continue
        k = int(above[0]) + 1
        count = count + 1 if k == cand else 1
        cand = k
        if count >= dwell_frames[k]:
            return i, k
        if fast_frames is not None and count >= fast_frames:
            rest = float(p[i].astype(np.float64).sum() - p[i, k])  # 1 - p_k without its rounding
            if np.log(p[i, k]) - np.log(max(rest, 1e-300)) >= log_odds:
                return i, k
    return None


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bank", required=True)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--modes", default="complete,stuck,hardover,null,loss=0.5")
    ap.add_argument("--rules", default="0.5")
    ap.add_argument("--cache", required=True)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    modes = args.modes.split(",")
    if os.path.exists(args.cache):
        data = np.load(args.cache, allow_pickle=True)
        meta, probs = list(data["meta"]), list(data["probs"])
    else:
        meta, probs = flights(args.bank, args.seed, args.runs, modes, args.workers)
        np.savez_compressed(args.cache, meta=np.array(meta, dtype=object), probs=np.array(probs, dtype=object))
    _, _, bank = load_bank(args.bank)
    threshold = float(bank.estimator_settings["threshold"])
    rate = float(bank.frame_rate_hz)
    hyps = names.SINGLE_HYPOTHESES
    for rule in args.rules.split(";"):
        dwell, fast, x = parse_rule(rule)
        frames = np.maximum(1, np.round(dwell * rate)).astype(int)
        fast_frames = None if fast is None else max(1, int(round(fast * rate)))
        print(f"dwell rule {rule}:")
        fa_total = 0
        for mode in ["none"] + modes:
            rows = [(m, c, t, p) for (m, c, t), p in zip(meta, probs) if m == mode]
            if not rows:
                continue
            fa = right = wrong = 0
            lat, wrong_names, fa_names = [], [], []
            for _, case, onset, p in rows:
                first = first_declaration(p, frames, threshold, fast_frames, x)
                t_first = None if first is None else first[0] / rate
                if first is not None and (onset is None or t_first < onset):
                    fa += 1
                    fa_names.append(f"FA:{hyps[first[1]]}")
                    continue
                if onset is None or first is None:
                    continue
                if hyps[first[1]] == case:
                    right += 1
                    lat.append(t_first - onset)
                else:
                    wrong += 1
                    wrong_names.append(f"{case}>{hyps[first[1]]}")
            fa_total += fa
            n_fail = sum(1 for r in rows if r[2] is not None)
            lat_txt = (f"latency median {np.median(lat):.2f} p95 {np.percentile(lat, 95):.2f} s" if lat else "")
            print(f"  {mode:9s} runs {len(rows):3d}  FA {fa:2d}  first right {right}/{n_fail}  first wrong {wrong}  "
                  f"{lat_txt}  {' '.join(wrong_names + fa_names)}")
        print(f"  FA runs in all: {fa_total}")


if __name__ == "__main__":
    main()
