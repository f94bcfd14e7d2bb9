"""The per-hypothesis evidence dwell N_k (``--dwell-nats-per-hypothesis FILE``,
cpp/f16mmae/declarer.h) from the false excursions of tuning flights.

Reads a single campaign's and a soak's ``runs.jsonl`` (tuning seeds: the tool refuses campaign
seed 1, the campaigns' evaluation default), flies every run again with its recorded scenario
and estimator settings, recording the probabilities, and follows the declaration rule frame by
frame: an *excursion* of hypothesis k is a run of consecutive frames on which p_k > threshold P
while k is not the current (presumed or last declared) hypothesis. Its evidence is the sum the
evidence dwell gathers,

    E = sum over its frames t < D of [ln(p_t / (1 - p_t)) - ln(P / (1 - P))],

D the frame dwell (16 frames). An excursion is *false* when k is not what the flight's truth
would have declared: any hypothesis but NONE in a soak flight or before a single run's failure,
any hypothesis but the failed single after it. A false excursion that ends before D frames is
one the frame dwell rejected; an evidence dwell of N_k nats would have declared it if E >= N_k.
So, per level-0 single k (the hypotheses whose first declaration the latency counts),

    N_k = max(floor, margin * E_max,k),   E_max,k = the largest E of k's false excursions
                                           rejected by the frame dwell (0 if none),

then, second step, N_k = 0 (``--frame-dwell-only``) for each single whose faster declaration added
a transient-wrong run or a false alarm when the tuning campaign is flown with the table (an earlier
declaration puts the level-1 bank on line earlier in the failure's transient, where a dual can
rise: a cost the excursions do not show). Every other hypothesis (NONE's back-out, the level-1
duals) is left out of the file: it
takes ``--dwell-nats`` (0: the frame dwell alone), so the second failures and the back-outs keep
the shipped rule. The file is one ``NAME N`` a line, the rule and its inputs in '#' comments;
``--tuning TOML`` also writes the table as that tuning's ``[estimator] dwell_nats_per_hypothesis``
(design/tuning.py), the key ``f16mmae design`` stores in the bank (each hypothesis' dwell_nats):

    f16mmae campaign single --runs 30 --seed 7 --baseline none --dwell-nats 0 --workers 1 --quiet --out SINGLE
    f16mmae campaign soak --hours 2 --seed 7 --dwell-nats 0 --workers 1 --quiet --out SOAK
    .venv/bin/python tools/latency/dwell_per_hypothesis.py SINGLE SOAK --margin 1.5 --floor 32 --out FILE \
        [--tuning python/harness/f16mmae/design/tunings/tuned.toml]
    python -m f16mmae.design.calibrate --banks     # the shipped banks with the tuning's table

The campaigns must fly the frame dwell alone (``--dwell-nats 0`` overrides a bank's own table);
the tool refuses campaigns flown with an evidence dwell.
"""
from __future__ import annotations

import argparse
import json
import math
import re
from pathlib import Path

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import NONE, SINGLE_HYPOTHESES

EVALUATION_SEED = 1


def excursions(names, p, declarations, time_s, threshold, dwell_frames, truth_of_frame):
    """Every excursion of a flight: dicts (hypothesis, start frame, frames, E over its first
    dwell_frames - 1 frames, false, rejected). ``p`` (frames, len(names)), NaN off line;
    ``declarations`` the flight's [{hypothesis, time_s}] (declared on the row of ``time_s``
    nearest, the row its dwell completed); ``truth_of_frame(i)`` the hypothesis
    the truth would have declared by frame i."""
    decl_frames = {int(np.argmin(np.abs(time_s - d["time_s"]))): d["hypothesis"] for d in declarations}
    current = NONE
    out, run = [], None
    ln_t = math.log(threshold / (1.0 - threshold))
    pz = np.nan_to_num(p, nan=0.0)
    above = pz > threshold
    for i in range(pz.shape[0]):
        cols = np.flatnonzero(above[i])
        k = names[cols[0]] if len(cols) else None
        if run is not None and (k != run["hypothesis"]):
            out.append(run)
            run = None
        if k is not None and k != current:
            if run is None:
                run = {"hypothesis": k, "start": i, "frames": 0, "E": 0.0,
                       "false": k != truth_of_frame(i)}
            run["frames"] += 1
            if run["frames"] < dwell_frames:
                x = float(pz[i, cols[0]])
                run["E"] += (math.inf if x >= 1.0 else math.log(x) - math.log1p(-x)) - ln_t
        elif run is not None:   # k became current (declared): close it
            out.append(run)
            run = None
        if i in decl_frames:   # declared on this frame (its dwell completed): current from now on
            current = decl_frames[i]
    if run is not None:
        out.append(run)
    for r in out:
        r["rejected"] = r["frames"] < dwell_frames
    return out


def flight_excursions(record, bank, threshold, dwell_frames):
    scenario = scenario_from_dict(record["scenario"])
    result = fly(scenario, bank, estimator_options=record["estimator"], record_probabilities=True)
    failures = record["scenario"].get("failures") or []
    fail_frame = int(np.searchsorted(np.asarray(result.time_s), failures[0]["time_s"] - 1e-9)) if failures else None
    failed = failures[0]["name"] if failures else None

    def truth_of_frame(i):
        return failed if fail_frame is not None and i >= fail_frame else NONE
    return excursions(list(result.hypotheses), result.probabilities, result.declarations,
                      np.asarray(result.time_s), threshold, dwell_frames, truth_of_frame), result


def campaign_records(d: Path):
    summary = json.loads((d / "summary.json").read_text())
    if summary.get("seed", EVALUATION_SEED) == EVALUATION_SEED:
        raise SystemExit(f"dwell_per_hypothesis: {d} is a campaign at seed {summary.get('seed')}, the "
                         f"evaluation default: derive N_k on tuning seeds (--seed 7)")
    return [json.loads(line) for line in (d / "runs.jsonl").read_text().splitlines() if line.strip()], summary


TUNING_KEY = "dwell_nats_per_hypothesis"


def write_tuning_key(path: Path, table: dict[str, float]) -> None:
    """Sets ``[estimator] dwell_nats_per_hypothesis = {NAME = N, ...}`` in the tuning file
    ``path`` (replacing the key's line, else appending it to ``[estimator]``, else appending the
    section); the file is read back by design/tuning.py to check it."""
    from f16mmae.design.tuning import load_tuning

    line = f"{TUNING_KEY} = {{" + ", ".join(f"{k} = {v:.1f}" for k, v in table.items()) + "}"
    text = path.read_text()
    lines = text.splitlines()
    sections = [i for i, ln in enumerate(lines) if re.match(r"\s*\[", ln)]
    est = next((i for i in sections if re.match(r"\s*\[estimator\]", lines[i])), None)
    if est is None:
        lines += ["", "[estimator]", line]
    else:
        end = next((i for i in sections if i > est), len(lines))
        at = next((i for i in range(est + 1, end) if re.match(rf"\s*{TUNING_KEY}\s*=", lines[i])), None)
        if at is not None:
            lines[at] = line
        else:
            while end > est + 1 and not lines[end - 1].strip():
                end -= 1
            lines.insert(end, line)
    path.write_text("\n".join(lines) + "\n")
    got = load_tuning(path).estimator.get(TUNING_KEY)
    if got != {k: round(v, 1) for k, v in table.items()}:
        raise SystemExit(f"dwell_per_hypothesis: {path} does not read back the table written")


def flown_frame_dwell(summary: dict, d: Path) -> None:
    """Refuses a campaign flown with an evidence dwell (the excursions must be the frame dwell's)."""
    s = summary.get("estimator_settings") or {}
    if s.get(TUNING_KEY) or float(s.get("dwell_nats", 0.0) or 0.0) > 0.0:
        raise SystemExit(f"dwell_per_hypothesis: {d} was flown with an evidence dwell "
                         f"({TUNING_KEY} or dwell_nats in its estimator_settings); fly the tuning "
                         "campaigns with --dwell-nats 0 (the frame dwell alone)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("single", type=Path, help="a tuning single campaign's directory")
    ap.add_argument("soak", type=Path, help="a tuning soak's directory")
    ap.add_argument("--margin", type=float, default=1.5)
    ap.add_argument("--floor", type=float, default=32.0)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--tuning", type=Path, default=None,
                    help="also write the table as this tuning file's [estimator] dwell_nats_per_hypothesis")
    ap.add_argument("--excursions", type=Path, default=None, help="also write every excursion (JSON lines)")
    ap.add_argument("--frame-dwell-only", default="",
                    help="comma list of singles given N_k = 0 (the frame dwell alone): those whose faster "
                         "declaration added a transient-wrong run or a false alarm on the tuning campaign "
                         "flown with the table (the second step of the rule)")
    ap.add_argument("--reuse", action="store_true",
                    help="read the excursions from --excursions (written by an earlier call on the same "
                         "campaigns) instead of flying the runs again")
    a = ap.parse_args()
    if not (a.margin >= 1.0 and math.isfinite(a.margin)):
        raise SystemExit(f"dwell_per_hypothesis: --margin must be >= 1, got {a.margin}")
    if not (0.0 < a.floor <= 1.0e6):
        raise SystemExit(f"dwell_per_hypothesis: --floor must lie in (0, 1e6] nats, got {a.floor}")
    single, s_sum = campaign_records(a.single)
    soak, k_sum = campaign_records(a.soak)
    flown_frame_dwell(s_sum, a.single)
    flown_frame_dwell(k_sum, a.soak)
    if s_sum.get("bank_hash") != k_sum.get("bank_hash"):
        raise SystemExit("dwell_per_hypothesis: the two campaigns flew different banks")
    _, _, bank = load_bank(s_sum.get("tuning") or "tuned")
    settings = s_sum.get("estimator_settings") or {}
    threshold = float(settings.get("threshold", 0.9))
    dwell_frames = max(1, int(round(float(settings.get("dwell_s", 0.25)) * float(bank.frame_rate_hz))))
    found = []
    if a.reuse:
        if a.excursions is None or not a.excursions.exists():
            raise SystemExit("dwell_per_hypothesis: --reuse needs the --excursions file of an earlier call")
        found = [json.loads(line) for line in a.excursions.read_text().splitlines() if line.strip()]
    else:
        for rec in single + soak:
            ex, _ = flight_excursions(rec, bank, threshold, dwell_frames)
            for e in ex:
                e["run"] = f"{rec.get('kind')}:{rec.get('case')}:{rec.get('run_index')}"
            found += ex
    if a.excursions and not a.reuse:
        a.excursions.write_text("".join(json.dumps(e) + "\n" for e in found))
    lines = [
        "# The per-hypothesis evidence dwell N_k (nats; cpp/f16mmae/declarer.h), written by",
        "# tools/latency/dwell_per_hypothesis.py from the tuning campaigns",
        f"#   single {a.single.name} (seed {s_sum.get('seed')}, {len(single)} runs), soak {a.soak.name} "
        f"(seed {k_sum.get('seed')}, {len(soak)} flights)",
        f"# N_k = max(floor {a.floor:g}, margin {a.margin:g} x E_max,k), E_max,k the largest log-odds excess",
        f"# a false excursion of k the {dwell_frames}-frame dwell rejected gathered (threshold {threshold:g}).",
        "# Hypotheses not named (NONE, the level-1 duals) take --dwell-nats (0: the frame dwell alone).",
    ]
    only = [k.strip().upper() for k in a.frame_dwell_only.split(",") if k.strip()]
    bad = [k for k in only if k not in SINGLE_HYPOTHESES or k == NONE]
    if bad:
        raise SystemExit(f"dwell_per_hypothesis: --frame-dwell-only {','.join(bad)}: not a failure hypothesis")
    if only:
        lines.append(f"# N_k = 0 (the frame dwell alone) for {', '.join(only)}: declared faster, they added a "
                     f"transient-wrong run or false alarm on the tuning campaign flown with the table.")
    lines.append("# NAME  N_k    # E_max,k, false excursions rejected / declared by the frame dwell")
    table = {}
    for k in SINGLE_HYPOTHESES:
        if k == NONE:
            continue
        fx = [e for e in found if e["hypothesis"] == k and e["false"]]
        rej = [e["E"] for e in fx if e["rejected"]]
        e_max = max(rej, default=0.0)
        n_k = max(a.floor, a.margin * e_max)
        n_k = 0.0 if k in only else min(n_k, 1.0e6)
        table[k] = n_k
        lines.append(f"{k:5s} {n_k:8.1f}   # {e_max:.1f}, {len(rej)} / {len(fx) - len(rej)}")
    a.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    if a.tuning is not None:
        write_tuning_key(a.tuning, table)
        print(f"wrote [estimator] {TUNING_KEY} to {a.tuning}; regenerate the banks "
              "(python -m f16mmae.design.calibrate --banks)")


if __name__ == "__main__":
    main()
