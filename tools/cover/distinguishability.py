"""How far the models separate a single failure from its duals (and two singles from each other),
and the per-dual allowance that asks a dual for evidence in proportion to how little they do.

For a bank file this redesigns the bank from its own metadata (tuning, flight condition, partial
losses; the gains are checked against the file's to 1e-9 of their scale) and evaluates, in
light turbulence with the dither on (``design.distinguish``: the truth's linear model, both
filters as the bank scores them, discrete Lyapunov plus the dither's periodic response):

    D_s(f>c) = D(f, f+c)   nats a frame: with f failed alone, how fast the level-1 bank's
                           log-odds ln(p_{f+c}/p_f) drift DOWN (the models' separation of the
                           single from the dual, the Kullback-Leibler rate of f+c's residual
                           density from f's when the models are exact);
    D_d(f>c) = D(f+c, f)   with f and c failed, how fast they climb (a real dual's drift).

With ``--level0 A,B`` it gives D(A, B) and D(B, A) at level 0 (the two singles' separation).

The allowance (cpp/f16mmae/level1_allowance.h): without a second failure the dual's log-odds
move by lambda = l_{f+c} - l_f a frame, E[lambda] = -D_s + m, m the part the linear models do
not explain (the closed loop, the nonlinear airframe, the gusts' spectrum) that the dual's extra
freedom (c's unknown position, or c's reading set free) absorbs. A walk reflected at the floor
with drift -D_s + m - k stays down only if k >= m - D_s: the less the models separate the pair,
the more evidence the dual must bring. With one mismatch rate m0 for all pairs,

    k(f>c) = min(k_max, max(0, m0 - D_s(f>c))),

zero for every dual the models separate faster than m0, and a real dual then climbs at
D_d - k. The table names, for each pair, the frames a real dual needs over the barrier h without
and with k (h / D_d, h / (D_d - k); never when D_d <= k).

Writes the file ``--level1-allowance-pairs FILE`` reads (``{"pairs": {"F>C": k}}``) with the
rates beside it:

  {"rule": "min(k_max, max(0, m0 - D_s))", "m0": m0, "k_max": k_max, "h_nats": h, "source": ...,
   "pairs": {"PIT>LS": k, ...}, "rates": {"PIT>LS": {"d_single": D_s, "d_dual": D_d}, ...}}

``--max-with TABLE``: each pair takes the larger of the models' k and TABLE's (e.g. the measured
table of tools/cover/dual_rates.py, which holds the walks the models do not predict).

Run: .venv/bin/python tools/cover/distinguishability.py BANK [--m0 0.2 --k-max 0.3] [--out FILE]
       [--print] [--level0 PIT,LS] [--pairs PIT>LS,...] [--max-with TABLE]   (all 132 pairs: minutes)
"""
from __future__ import annotations

import argparse
import json
import math
import pathlib
import sys

FRAME_RATE_HZ = 64.0


def barrier(threshold: float, p_min: float) -> float:
    """h: the log-odds from the floor p_min to the threshold T, nats."""
    return math.log(threshold / (1.0 - threshold)) - math.log(p_min / (1.0 - p_min))


def allowance(d_single: float, m0: float, k_max: float) -> float:
    """k = min(k_max, max(0, m0 - D_s)), nats a frame (module docstring)."""
    if not (m0 >= 0.0 and k_max >= 0.0 and math.isfinite(m0) and math.isfinite(k_max)):
        raise ValueError(f"m0 and k_max must be finite and >= 0, got {m0!r}, {k_max!r}")
    if not math.isfinite(d_single):
        raise ValueError(f"D_s must be finite, got {d_single!r}")
    return min(k_max, max(0.0, m0 - d_single))


def climb_frames(d_dual: float, k: float, h: float) -> float:
    """Frames a real dual drifting at D_d needs to climb h with the allowance k (inf if D_d <= k)."""
    return math.inf if d_dual <= k else h / (d_dual - k)


def pair_table(rates: dict[str, dict], m0: float, k_max: float) -> dict[str, float]:
    """{"F>C": k} from {"F>C": {"d_single": D_s, "d_dual": D_d}}."""
    return {pair: allowance(r["d_single"], m0, k_max) for pair, r in sorted(rates.items())}


def combine(table: dict[str, float], other: dict[str, float]) -> dict[str, float]:
    """Each pair's larger k of the two tables (a pair in one only keeps its k)."""
    return {pair: max(table.get(pair, 0.0), float(other.get(pair, 0.0))) for pair in sorted(set(table) | set(other))}


def bank_design(path: str):
    """(bank, design): the bank file and its redesign (campaign.dual.models.bank_design: the
    tuning its metadata records, gains checked); ValueError naming the problem."""
    from f16mmae import core
    from f16mmae.campaign.dual.models import bank_design as redesign

    if not pathlib.Path(path).is_file():
        raise ValueError(f"bank {path!r}: no such file")
    bank = core.load_bank(path)
    design, why = redesign(bank)
    if design is None:
        raise ValueError(f"bank {path!r}: {why}")
    return bank, design


def dual_rates(design, pairs: list[tuple[str, str]]) -> dict[str, dict]:
    """{"F>C": {"d_single": D(F, F+C), "d_dual": D(F+C, F)}}, light air, dither on."""
    from f16mmae import names
    from f16mmae.design import distinguish

    out: dict[str, dict] = {}
    by_first: dict[str, list[str]] = {}
    for f, c in pairs:
        by_first.setdefault(f, []).append(c)
    for f, cs in by_first.items():
        duals = [names.dual_name(f, c) for c in cs]
        down = distinguish.evidence_rates(design, f, duals)
        for c, d in zip(cs, duals):
            up = distinguish.evidence_rates(design, d, [f])[f]
            out[f"{f}>{c}"] = {"d_single": float(down[d]), "d_dual": float(up)}
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bank")
    ap.add_argument("--m0", type=float, default=0.2, help="the mismatch rate m0, nats a frame")
    ap.add_argument("--k-max", type=float, default=0.3, help="the ceiling of k, nats a frame")
    ap.add_argument("--pairs", default="", help="F>C,... (default: every ordered pair of singles)")
    ap.add_argument("--level0", default="", help="A,B: the two singles' separation at level 0 as well")
    ap.add_argument("--max-with", default="",
                    help="a pair table (e.g. tools/cover/dual_rates.py's): each pair takes the larger of its k there "
                         "and the models' k")
    ap.add_argument("--out", default="")
    ap.add_argument("--print", action="store_true")
    args = ap.parse_args(argv)
    try:
        allowance(0.0, args.m0, args.k_max)
        from f16mmae import names
        singles = list(names.SINGLE_HYPOTHESES[1:])
        if args.pairs:
            pairs = []
            for key in args.pairs.split(","):
                f, _, c = key.partition(">")
                if f not in singles or c not in singles or f == c:
                    raise ValueError(f"--pairs: {key!r} is not F>C with F, C two different singles ({','.join(singles)})")
                pairs.append((f, c))
        else:
            pairs = [(f, c) for f in singles for c in singles if f != c]
        level0 = args.level0.split(",") if args.level0 else []
        if level0 and (len(level0) != 2 or not all(x in names.SINGLE_HYPOTHESES for x in level0)):
            raise ValueError(f"--level0: {args.level0!r} is not two hypotheses of the level-0 bank")
        other = {}
        if args.max_with:
            try:
                other = json.loads(pathlib.Path(args.max_with).read_text())["pairs"]
            except (OSError, ValueError, KeyError, TypeError) as exc:
                raise ValueError(f"--max-with {args.max_with!r}: not a pair table ({exc})") from None
        bank, design = bank_design(args.bank)
    except ValueError as exc:
        print(f"distinguishability: {exc}", file=sys.stderr)
        return 2
    from f16mmae.design import distinguish

    h = barrier(bank.threshold, bank.p_min)
    rates = dual_rates(design, pairs)
    table = pair_table(rates, args.m0, args.k_max)
    if other:
        table = combine(table, other)
    if level0:
        a, b = level0
        ab = distinguish.evidence_rates(design, a, [b])[b]
        ba = distinguish.evidence_rates(design, b, [a])[a]
        print(f"level 0: D({a}, {b}) = {ab:.4f} nats a frame (truth {a}), D({b}, {a}) = {ba:.4f} (truth {b})")
    if args.print:
        print(f"h = {h:.1f} nats; k = min({args.k_max:g}, max(0, {args.m0:g} - D_s))")
        print("| pair | D_s (single truth) | D_d (dual truth) | k | real dual's climb, s: without / with k |")
        print("|---|---|---|---|---|")
        for pair, r in sorted(rates.items(), key=lambda kv: kv[1]["d_single"]):
            k = table[pair]
            without = climb_frames(r["d_dual"], 0.0, h) / FRAME_RATE_HZ
            with_k = climb_frames(r["d_dual"], k, h) / FRAME_RATE_HZ
            print(f"| {pair} | {r['d_single']:.4f} | {r['d_dual']:.4f} | {k:.3f} | "
                  f"{without:.2f} / {'never' if math.isinf(with_k) else f'{with_k:.2f}'} |")
    if args.out:
        rule = "min(k_max, max(0, m0 - D_s))" + (f", or {args.max_with}'s k where larger" if other else "")
        out = {"rule": rule, "m0": args.m0, "k_max": args.k_max, "h_nats": h,
               "frame_rate_hz": FRAME_RATE_HZ,
               "source": f"design.distinguish on bank {bank.content_hash[:12]} ({bank.tuning}), light air, dither on",
               "pairs": table, "rates": rates}
        pathlib.Path(args.out).write_text(json.dumps(out, indent=1, sort_keys=True) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
