"""Lab driver (not in the wheel), an experiment: a schedule with every node's adaptation reference
raised to at least MIN_REFERENCE (the nodes whose calibration met no false-alarm bound sit at
the bisection's lowest, calibrate.REFERENCE_RANGE[0]); nothing else changed.

    python tools/schedule/node_reference.py SCHEDULE OUT MIN_REFERENCE [M:FT,...]

With the node list, only those nodes (both layers) are raised.  Writes OUT and prints the nodes
it moved, OUT and its content hash."""
import json
import sys

import numpy as np

from f16mmae import core

src, out, floor = sys.argv[1], sys.argv[2], float(sys.argv[3])
only = None if len(sys.argv) < 5 else {tuple(float(x) for x in item.split(":")) for item in sys.argv[4].split(",")}
s = core.load_bank(src).schedule
nodes = []
for n in s["nodes"]:
    chosen = only is None or (float(n["mach"]), float(n["alt_ft"])) in only
    ref = max(float(n["adapt_reference"]), floor) if chosen else n["adapt_reference"]
    if ref != n["adapt_reference"]:
        print(f"Mach {n['mach']}, {n['alt_ft']:.0f} ft (layer {n['layer']}): {n['adapt_reference']} -> {ref}")
    nodes.append((n["i_mach"], n["i_alt"], n["bank"], np.array(n["x_trim"]), ref, n["layer"]))
meta = json.loads(s["metadata"])
meta["experiment"] = (meta.get("experiment", "") + f"; reference at least {floor}").lstrip("; ")
h = core.save_schedule(list(s["mach"]), list(s["alt_ft"]), nodes, primary=s["primary"],
                       metadata=json.dumps(meta, sort_keys=True, separators=(",", ":")), path=out,
                       switch_state=s["switch_state"], switch_thresholds=list(s["switch_thresholds"]),
                       start_up_s=s["start_up_s"])
print(out, h[:12])
