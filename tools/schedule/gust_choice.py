"""Lab driver (not in the wheel): the file ``design --schedule --gust-states-below-ft FT
--gust-node-choice effort`` designs, assembled from two designed files of the same grid and
tuning instead of designing every low node twice.

    python tools/schedule/gust_choice.py PLAIN.f16sched GUST.f16sched OUT.f16sched [--show]

PLAIN: the schedule without gust states (``design --schedule``); GUST: the same with every
node at or below FT carrying them (``--gust-states-below-ft FT``, choice ``all``). A node's
design, trim and calibration record do not depend on its neighbours, so each node (and its
flap-layer alternates) is taken from the file of its choice (``schedule.gust_gains`` on the
two files' records), the plain ones padded (``gust_states.pad_bank``), and the floors and
references are the neighbourhood rule's (``schedule.neighbourhood_settings`` with the kept
interior ``schedule.gust_neighbourhoods``), as ``design_schedule`` sets them.  The metadata is
GUST's with the nodes' records, the gust-state block and the command of the choice.
``--plain-nodes M:FT,...``: those low nodes plain, the others with gust states, in place of the
effort choice (for a diagnosis).  ``--show``: print each low node's choice and the floors and references of the rows up to
the first row above FT, and write nothing if OUT is ``-``.
"""
from __future__ import annotations

import argparse
import json

from f16mmae import core
from f16mmae.design.gust_states import pad_bank, pad_state
from f16mmae.design.schedule import floor_effort, gust_gains, gust_neighbourhoods, neighbourhood_settings


def _records(meta: dict, mach, alt) -> dict:
    """grid index -> the node's calibration record with its own chosen floor and reference
    (the file's records hold the neighbourhood's as p_min / adapt_reference)."""
    out = {}
    for r in meta["nodes"]:
        k = (mach.index(r["mach"]), alt.index(r["alt_ft"]))
        out[k] = dict(r, p_min=r["p_min_node"], adapt_reference=r["adapt_reference_node"])
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plain")
    ap.add_argument("gust")
    ap.add_argument("out")
    ap.add_argument("--show", action="store_true")
    ap.add_argument("--plain-nodes", default=None, metavar="M:FT,...",
                    help="instead of the effort choice, these low nodes plain and the others with gust states "
                         "(a hand-made choice: the metadata's command does not name it)")
    args = ap.parse_args()
    p, g = core.load_bank(args.plain).schedule, core.load_bank(args.gust).schedule
    if list(p["mach"]) != list(g["mach"]) or list(p["alt_ft"]) != list(g["alt_ft"]):
        raise SystemExit("the two files' grids differ")
    mach, alt = list(g["mach"]), list(g["alt_ft"])
    pm, gm = json.loads(p["metadata"]), json.loads(g["metadata"])
    if "gust_states" not in gm or "gust_states" in pm:
        raise SystemExit("give the plain file first, then the file with gust states below FT")
    if pm["command"] + f" --gust-states-below-ft {gm['gust_states']['below_ft']:g}" != gm["command"]:
        raise SystemExit(f"the files are not the same design with and without gust states:\n  {pm['command']}\n  "
                         f"{gm['command']}")
    rp, rg = _records(pm, mach, alt), _records(gm, mach, alt)
    low = {(mach.index(n["mach"]), alt.index(n["alt_ft"])) for n in gm["gust_states"]["nodes"]}
    choice = {k: {"gust": gust_gains(rp[k], rg[k]), "effort_plain": floor_effort(rp[k])[1],
                  "effort_gust": floor_effort(rg[k])[1]}
              for k in sorted(low) if k in rp and k in rg}
    if args.plain_nodes is not None:
        plain = {(mach.index(float(m)), alt.index(float(a))) for m, a in
                 (x.split(":") for x in args.plain_nodes.split(",") if x)}
        for k in choice:
            choice[k]["gust"] = k not in plain
    gust = {k for k, c in choice.items() if c["gust"]}
    records = {k: (rg[k] if k in gust else rp[k]) for k in rp}
    keep = gust_neighbourhoods(records, gust)
    floors, refs = neighbourhood_settings(records, keep_own=keep)
    if args.show:
        for k, c in choice.items():
            print(f"Mach {mach[k[0]]:.2f} {alt[k[1]]:6.0f} ft: {'gust ' if c['gust'] else 'plain'} "
                  f"(effort at the smallest floor {c['effort_gust']} with, {c['effort_plain']} without)")
        top = max(k[1] for k in low) + 1
        for j in range(top + 1):
            print(f"{alt[j]:6.0f} " + " ".join(f"{'G' if (i, j) in gust else 'P'}{floors[(i, j)]:.0e}/{refs[(i, j)]:.2f}"
                                              for i in range(len(mach)) if (i, j) in floors))
    if args.out == "-":
        return 0
    nodes = []
    src = {"p": {(n["i_mach"], n["i_alt"], n["layer"]): n for n in p["nodes"]},
           "g": {(n["i_mach"], n["i_alt"], n["layer"]): n for n in g["nodes"]}}
    for n in g["nodes"]:   # GUST's order: the grid, then the alternates
        k = (n["i_mach"], n["i_alt"])
        m = n if k in gust or k not in low else src["p"][(k[0], k[1], n["layer"])]
        bank = pad_bank(m["bank"]).with_settings(p_min=floors[k])
        nodes.append((k[0], k[1], bank, pad_state(m["x_trim"]), refs[k], m["layer"]))
    meta = dict(gm)
    meta["command"] = gm["command"] + (" --gust-node-choice effort" if args.plain_nodes is None else "")
    plain_records = {(r["mach"], r["alt_ft"]): r for r in pm["nodes"]}
    file_records = []
    for r in gm["nodes"]:
        k = (mach.index(r["mach"]), alt.index(r["alt_ft"]))
        base = plain_records[(r["mach"], r["alt_ft"])] if k in low and k not in gust else r
        file_records.append(dict(base, p_min=floors[k], adapt_reference=refs[k]))
    meta["nodes"] = file_records
    gs = dict(gm["gust_states"])
    gs["nodes"] = [{"mach": mach[i], "alt_ft": alt[j]} for (i, j) in sorted(gust, key=lambda k: (k[1], k[0]))]
    gs["own_settings"] = [{"mach": mach[i], "alt_ft": alt[j]} for (i, j) in sorted(keep, key=lambda k: (k[1], k[0]))]
    gs["choice"] = "effort" if args.plain_nodes is None else f"plain at {args.plain_nodes}"
    gs["efforts"] = [{"mach": mach[i], "alt_ft": alt[j], **choice[(i, j)]}
                     for (i, j) in sorted(choice, key=lambda k: (k[1], k[0]))]
    meta["gust_states"] = gs
    h = core.save_schedule(mach, alt, nodes, primary=g["primary"],
                           metadata=json.dumps(meta, sort_keys=True, separators=(",", ":")), path=args.out,
                           switch_state=g["switch_state"], switch_thresholds=list(g["switch_thresholds"]),
                           start_up_s=g["start_up_s"])
    print(f"{args.out}: {len(nodes)} banks, gust states at {len(gust)} of {len(low)} low nodes, content hash {h[:12]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
