"""Lab driver (not in the wheel): a scheduled bank whose nodes at or above an altitude take the
turbulence adaptation's reference rho_0 times a factor (capped at 100, the option's bound);
nothing else changed.

    python tools/schedule/reference_scale.py SCHEDULE OUT FACTOR MIN_ALT_FT

Writes OUT and prints it and its content hash.  With FACTOR 7/6 (1.1666667) this offsets, at
those nodes, the rise of rho that own channels (``--adapt-own-channels``) gives a hypothesis
reading six of the seven channels (turbulence_adaptation.h)."""
from __future__ import annotations

import argparse
import sys

import numpy as np

from schedule_edit import load_schedule, number, save_edited


def _positive(text: str, what: str) -> float:
    return number(text, what, True)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("schedule", metavar="SCHEDULE", help="the scheduled-bank file to edit")
    p.add_argument("out", metavar="OUT", help="the edited file to write")
    p.add_argument("factor", metavar="FACTOR", type=lambda t: _positive(t, "FACTOR"), help="the references' factor (> 0)")
    p.add_argument("min_alt_ft", metavar="MIN_ALT_FT", type=lambda t: _positive(t, "MIN_ALT_FT"),
                   help="nodes at or above this altitude, ft (> 0)")
    a = p.parse_args(argv)
    s = load_schedule(p, a.schedule)
    nodes, changed = [], 0
    for n in s["nodes"]:
        nb, ref = n["bank"], n["adapt_reference"]
        if nb.alt_ft >= a.min_alt_ft:
            ref, changed = min(100.0, ref * a.factor), changed + 1
        nodes.append((n["i_mach"], n["i_alt"], nb, np.array(n["x_trim"]), ref, n["layer"]))
    if changed == 0:
        p.error(f"MIN_ALT_FT {a.min_alt_ft:g}: no node at or above it (highest {max(x[2].alt_ft for x in nodes):g} ft)")
    save_edited(s, nodes, a.out, f"adapt_reference x {a.factor:g} at nodes >= {a.min_alt_ft:g} ft")
    return 0


if __name__ == "__main__":
    sys.exit(main())
