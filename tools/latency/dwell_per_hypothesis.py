"""The per-hypothesis evidence dwell N_k (``--dwell-nats-per-hypothesis FILE``,
cpp/f16mmae/declarer.h) from the false excursions of tuning flights.

Reads the ``runs.jsonl`` of tuning campaigns -- single, envelope and maneuver campaigns (one
failure a run) and soaks (none), any number of them, all of one bank (the tool refuses the
evaluation seeds 1 and 2) -- flies every run again with its recorded scenario and estimator
settings, recording the probabilities, and follows the declaration rule frame by frame: an
*excursion* of hypothesis k is a run of consecutive frames on which p_k > threshold P while k
is not the current (presumed or last declared) hypothesis. Its evidence is the sum the evidence
dwell gathers over its frames before it ends or is declared,

    E = sum over its frames t of [ln(p_t / (1 - p_t)) - ln(P / (1 - P))].

An excursion is *false* when k is not what the flight's truth would have declared: any
hypothesis but NONE in a soak flight or before a run's failure, any hypothesis but the failed
single after it. A false excursion that ends without k's declaration is one the frame dwell in
force rejected (16 frames, or a least dwell, a maneuver's or the rough air's longer one). On
frame t of an excursion the evidence dwell asks N_k f_t / D nats of the sum so far E_t, f_t the
dwell in frames in force for the candidate on that frame (the flight records it:
``FlightResult.dwell_frames_in_force``, the phase's dwell or k's least dwell, rough air's in rough
air, the longer) and D the declarer's own dwell in frames: an evidence dwell of N_k nats would
have declared the excursion on its first frame with E_t D / f_t >= N_k, so it stays rejected for
every N_k above the excursion's bound

    B = max over its frames t of E_t D / f_t        (exact: f_t as the declarer had it).

So, per level-0 single k (the hypotheses whose first declaration the latency counts),

    N_k = max(floor, margin * E_max,k),   E_max,k = the largest B of k's false excursions
                                           rejected by the dwell in force (0 if none),

then, second step, N_k = 0 (``--frame-dwell-only``) for each single whose faster declaration added
a transient-wrong run or a false alarm when the tuning campaigns are flown with the table (an earlier
declaration puts the level-1 bank on line earlier in the failure's transient, where a dual can
rise: a cost the excursions do not show). Every other hypothesis (NONE's back-out, the level-1
duals) is left out of the file: it
takes ``--dwell-nats`` (0: the frame dwell alone), so the second failures and the back-outs keep
the shipped rule. The file is one ``NAME N`` a line, the rule and its inputs in '#' comments,
under each N_k the run and frames of the excursion that set it and the ``f16mmae run`` command
that flies that run again;
``--tuning TOML`` also writes the table as that tuning's ``[estimator] dwell_nats_per_hypothesis``
(design/tuning.py), the key ``f16mmae design`` stores in the bank (each hypothesis' dwell_nats):

    f16mmae campaign single --runs 30 --seed 7 --baseline none --dwell-nats 0 --workers 1 --quiet --out SINGLE
    f16mmae campaign soak --hours 2 --seed 7 --dwell-nats 0 --workers 1 --quiet --out SOAK
    .venv/bin/python tools/latency/dwell_per_hypothesis.py SINGLE SOAK --margin 1.5 --floor 32 --out FILE \
        [--tuning python/harness/f16mmae/design/tunings/tuned.toml]
    python -m f16mmae.design.calibrate --banks     # the shipped banks with the tuning's table

The scheduled estimator's table (names.SCHEDULE_DWELL_NATS_PER_HYPOTHESIS) comes from the
tuning seeds' single campaigns at every level (failures at 3 s and at 20-21 s), the maneuver
campaign, 60 random points and the soaks at the nominal point and the trimmable edge, pilotless
and holding, all flown with ``--tuning scheduled --adapt-turbulence --dwell-nats 0``
(docs/results/detection_latency.md, round 42, lists the commands):

    .venv/bin/python tools/latency/dwell_per_hypothesis.py SINGLE SETTLED MANEUVER ENVELOPE SOAK... \
        --margin 1.5 --floor 32 --workers 2 --out FILE

The campaigns must fly the frame dwell alone (``--dwell-nats 0`` overrides a bank's own table);
the tool refuses campaigns flown with an evidence dwell. Every flight flown again must declare
what its record says (the tool counts and names any that do not: a record of other code).
"""
from __future__ import annotations

import argparse
import json
import math
import re
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from f16mmae.banks import load_bank
from f16mmae.campaign.engine.drilldown import flies_as_recorded, record_command
from f16mmae.loop.flight import fly, scenario_from_dict
from f16mmae.names import NONE, SINGLE_HYPOTHESES

#: The evaluation seed (the campaigns' default) and the held-out one: never tuned on.
EVALUATION_SEEDS = (1, 2)


def excursions(names, p, declarations, time_s, threshold, truth_of_frame, frames_in_force=None, dwell_frames=16):
    """Every excursion of a flight: dicts (hypothesis, start frame, frames, E over its frames up
    to its end or its declaration, B its bound max_t E_t dwell_frames / f_t, false, rejected: it
    ended without its declaration). ``p`` (frames, len(names)), NaN off line; ``declarations``
    the flight's [{hypothesis, time_s}] (declared on the row of ``time_s`` nearest, the row its
    dwell completed); ``truth_of_frame(i)`` the hypothesis the truth would have declared by frame
    i; ``frames_in_force`` (frames,) the declarer's dwell in frames for its candidate after each
    frame (None: ``dwell_frames`` on every frame), never below ``dwell_frames``."""
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
                run = {"hypothesis": k, "start": i, "frames": 0, "E": 0.0, "B": 0.0,
                       "false": k != truth_of_frame(i), "rejected": True}
            run["frames"] += 1
            x = float(pz[i, cols[0]])
            run["E"] += (math.inf if x >= 1.0 else math.log(x) - math.log1p(-x)) - ln_t
            f = dwell_frames if frames_in_force is None else max(int(frames_in_force[i]), dwell_frames)
            run["B"] = max(run["B"], run["E"] * dwell_frames / f)
        elif run is not None:   # k became current (declared): close it
            out.append(run)
            run = None
        if i in decl_frames:   # declared on this frame (its dwell completed): current from now on
            current = decl_frames[i]
            if run is not None and run["hypothesis"] == current:
                run["rejected"] = False
    if run is not None:
        out.append(run)
    return out


def flight_excursions(record, bank, threshold):
    scenario = scenario_from_dict(record["scenario"])
    # the frame dwell alone, as flown (flown_frame_dwell): --dwell-nats 0 keeps a default table out
    options = {**record["estimator"], "dwell_nats": 0.0}
    result = fly(scenario, bank, estimator_options=options, record_probabilities=True)
    failures = record["scenario"].get("failures") or []
    fail_frame = int(np.searchsorted(np.asarray(result.time_s), failures[0]["time_s"] - 1e-9)) if failures else None
    failed = failures[0]["name"] if failures else None

    def truth_of_frame(i):
        return failed if fail_frame is not None and i >= fail_frame else NONE
    dwell = max(1, round(float(result.estimator_settings.get("dwell_s", 0.25)) * float(bank.frame_rate_hz)))
    found = excursions(list(result.hypotheses), result.probabilities, result.declarations,
                       np.asarray(result.time_s), threshold, truth_of_frame,
                       frames_in_force=result.dwell_frames_in_force, dwell_frames=dwell)
    return found, result


def run_label(d: Path, seed, record: dict) -> str:
    """A run's name in the excursions: its campaign directory and campaign seed, kind, point,
    maneuver, turbulence, case and run index (one run of the tool's campaigns each)."""
    scenario = record.get("scenario") or {}
    return ":".join(str(x) for x in (f"{d.name}@seed{seed}", record.get("kind"), record.get("point") or "-",
                                     record.get("maneuver") or "-", scenario.get("turbulence"),
                                     record.get("case"), record.get("run_index")))


def provenance(excursion: dict, commands: dict[str, str]) -> str:
    """The comment line under a hypothesis' N_k naming the excursion that set E_max,k: its run,
    first frame and length, and the command that flies that run again (frame dwell alone, as the
    tuning campaign flew it)."""
    command = commands.get(excursion["run"], "(run not among the campaigns read)")
    return (f"#   largest: {excursion['run']}, frames {excursion['start']}-"
            f"{excursion['start'] + excursion['frames'] - 1}: {command}")


def campaign_records(d: Path):
    summary = json.loads((d / "summary.json").read_text())
    if summary.get("seed", EVALUATION_SEEDS[0]) in EVALUATION_SEEDS:
        raise SystemExit(f"dwell_per_hypothesis: {d} is a campaign at seed {summary.get('seed')}, an "
                         f"evaluation seed ({', '.join(map(str, EVALUATION_SEEDS))}): derive N_k on "
                         "tuning seeds (--seed 7)")
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


def flown_frame_dwell(records: list, summary: dict, d: Path) -> None:
    """Refuses a campaign flown with an evidence dwell (the excursions must be the frame dwell's):
    its settings or any run's (a scheduled bank's defaults are in the runs' settings)."""
    for s in [summary.get("estimator_settings") or {}] + [r.get("estimator_settings") or {} for r in records]:
        if s.get(TUNING_KEY) or float(s.get("dwell_nats", 0.0) or 0.0) > 0.0:
            raise SystemExit(f"dwell_per_hypothesis: {d} was flown with an evidence dwell "
                             f"({TUNING_KEY} or dwell_nats in its estimator settings); fly the tuning "
                             "campaigns with --dwell-nats 0 (the frame dwell alone)")


_BANK = None


def _load(tuning: str) -> None:
    global _BANK
    _, _, _BANK = load_bank(tuning)


def _fly(args):
    """One record flown again (a worker's task): its excursions, labelled, and whether it
    declared as recorded."""
    record, threshold, label = args
    ex, result = flight_excursions(record, _BANK, threshold)
    for e in ex:
        e["run"] = label
    return ex, flies_as_recorded(record, result.declarations), label


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("campaigns", type=Path, nargs="+",
                    help="tuning campaigns' directories (single, envelope, maneuver, soak), one bank")
    ap.add_argument("--margin", type=float, default=1.5)
    ap.add_argument("--floor", type=float, default=32.0)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--workers", type=int, default=1, help="processes flying the runs again (default 1)")
    ap.add_argument("--tuning", type=Path, default=None,
                    help="also write the table as this tuning file's [estimator] dwell_nats_per_hypothesis")
    ap.add_argument("--excursions", type=Path, default=None, help="also write every excursion (JSON lines)")
    ap.add_argument("--frame-dwell-only", default="",
                    help="comma list of singles given N_k = 0 (the frame dwell alone): those whose faster "
                         "declaration added a transient-wrong run or a false alarm on the tuning campaigns "
                         "flown with the table (the second step of the rule)")
    ap.add_argument("--reuse", action="store_true",
                    help="read the excursions from --excursions (written by an earlier call on the same "
                         "campaigns) instead of flying the runs again")
    a = ap.parse_args()
    if not (a.margin >= 1.0 and math.isfinite(a.margin)):
        raise SystemExit(f"dwell_per_hypothesis: --margin must be >= 1, got {a.margin}")
    if not (0.0 < a.floor <= 1.0e6):
        raise SystemExit(f"dwell_per_hypothesis: --floor must lie in (0, 1e6] nats, got {a.floor}")
    if not 1 <= a.workers <= 256:
        raise SystemExit(f"dwell_per_hypothesis: --workers must lie in [1, 256], got {a.workers}")
    only = [k.strip().upper() for k in a.frame_dwell_only.split(",") if k.strip()]
    bad = [k for k in only if k not in SINGLE_HYPOTHESES or k == NONE]
    if bad:
        raise SystemExit(f"dwell_per_hypothesis: --frame-dwell-only {','.join(bad)}: not a failure hypothesis")
    if a.reuse and (a.excursions is None or not a.excursions.exists()):
        raise SystemExit("dwell_per_hypothesis: --reuse needs the --excursions file of an earlier call")
    for path in [a.out] + ([a.excursions] if a.excursions and not a.reuse else []):
        if not path.parent.is_dir():
            raise SystemExit(f"dwell_per_hypothesis: cannot write {path}: no directory {path.parent}")
    loaded = [(d, *campaign_records(d)) for d in a.campaigns]
    # the commands fly the frame dwell alone, as the tool does (a scheduled default's table is off)
    commands = {run_label(d, summary.get("seed"), rec):
                record_command({**rec, "estimator": {**rec["estimator"], "dwell_nats": 0.0}})
                for d, records, summary in loaded for rec in records}
    for d, records, summary in loaded:
        flown_frame_dwell(records, summary, d)
    first = loaded[0][2]
    for d, _, summary in loaded[1:]:
        if summary.get("bank_hash") != first.get("bank_hash"):
            raise SystemExit(f"dwell_per_hypothesis: {d} flew another bank than {loaded[0][0]}")
    tuning = first.get("tuning") or "tuned"
    _, _, bank = load_bank(tuning)
    settings = first.get("estimator_settings") or {}
    threshold = float(settings.get("threshold", 0.9))
    found = []
    if a.reuse:
        found = [json.loads(line) for line in a.excursions.read_text().splitlines() if line.strip()]
    else:
        tasks = [(rec, threshold, run_label(d, summary.get("seed"), rec))
                 for d, records, summary in loaded for rec in records]
        differ = []
        with ProcessPoolExecutor(a.workers, initializer=_load, initargs=(tuning,)) as pool:
            for n, (ex, same, label) in enumerate(pool.map(_fly, tasks, chunksize=4), 1):
                found += ex
                if not same:
                    differ.append(label)
                if n % 200 == 0 or n == len(tasks):
                    print(f"flown again {n}/{len(tasks)}", file=sys.stderr, flush=True)
        if differ:
            raise SystemExit(f"dwell_per_hypothesis: {len(differ)} of {len(tasks)} flights flown again declare "
                             f"otherwise than recorded (records of other code?), e.g. {', '.join(differ[:5])}")
    if a.excursions and not a.reuse:
        a.excursions.write_text("".join(json.dumps(e) + "\n" for e in found))
    names = ", ".join(f"{d.name} ({s.get('kind', '?')}, seed {s.get('seed')}, {len(r)} flights)" for d, r, s in loaded)
    lines = [
        "# The per-hypothesis evidence dwell N_k (nats; cpp/f16mmae/declarer.h), written by",
        "# tools/latency/dwell_per_hypothesis.py from the tuning campaigns",
        f"#   {names}",
        f"# N_k = max(floor {a.floor:g}, margin {a.margin:g} x E_max,k), E_max,k the largest log-odds excess",
        f"# a false excursion of k gathered that the dwell in force rejected (threshold {threshold:g}), each",
        "# frame's sum over the dwell in frames in force for it then, in dwells of the declarer.",
        "# Hypotheses not named (NONE, the level-1 duals) take --dwell-nats (0: the frame dwell alone).",
    ]
    if only:
        lines.append(f"# N_k = 0 (the frame dwell alone) for {', '.join(only)}: declared faster, they added a "
                     f"transient-wrong run or false alarm on the tuning campaigns flown with the table.")
    lines.append("# NAME  N_k    # E_max,k, false excursions rejected / declared by the dwell in force;")
    lines.append("#   largest: the run and frames that set E_max,k, and the command that flies it again")
    table = {}
    for k in SINGLE_HYPOTHESES:
        if k == NONE:
            continue
        fx = [e for e in found if e["hypothesis"] == k and e["false"]]
        rej = [e["B"] for e in fx if e["rejected"]]
        e_max = max(rej, default=0.0)
        largest = max((e for e in fx if e["rejected"]), key=lambda e: e["B"], default=None)
        n_k = max(a.floor, a.margin * e_max)
        n_k = 0.0 if k in only else min(n_k, 1.0e6)
        table[k] = n_k
        lines.append(f"{k:5s} {n_k:8.1f}   # {e_max:.1f}, {len(rej)} / {len(fx) - len(rej)}")
        if largest is not None:
            lines.append(provenance(largest, commands))
    a.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    if a.tuning is not None:
        write_tuning_key(a.tuning, table)
        print(f"wrote [estimator] {TUNING_KEY} to {a.tuning}; regenerate the banks "
              "(python -m f16mmae.design.calibrate --banks)")


if __name__ == "__main__":
    main()
