"""Lab driver (not in the wheel): a scheduled bank whose failed-sensor hypotheses at every node
take a failed SENSOR (default VEL) as reading an unknown constant level within a window of
width W (sensor units; the cover model's uniform prior, narrowed from the sensor's full range
to the trim's uncertainty), the level a random walk of LEVEL_Q per frame (hypotheses.py's
`cover` density and level filter, steady_state_filter.h).

    python tools/schedule/failed_sensor_window.py SCHEDULE OUT W LEVEL_Q [SENSOR [START_UP_S]]

Writes OUT: SCHEDULE with every node's SENSOR-failed hypotheses (SENSOR and SENSOR+c) so
changed and the start-up START_UP_S recommended (default 0.25); nothing else changed.
Prints OUT and its content hash.  With W = 9.9 and LEVEL_Q = 2.5e-7 (1e-6 of VEL's noise
variance) these are the hypotheses of design/hypotheses.py's `constant` model for VEL, the
filter matrices being the `complete` model's (for AOA: W = 6 TRIM_SIGMA["AOA"], LEVEL_Q 1e-6
of AOA's noise variance)."""
from __future__ import annotations

import argparse
import sys

import numpy as np

from f16mmae import core, names
from schedule_edit import load_schedule, number as _number, save_edited


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("schedule", metavar="SCHEDULE", help="the scheduled-bank file to edit (f16mmae design --schedule)")
    p.add_argument("out", metavar="OUT", help="the edited scheduled-bank file to write")
    p.add_argument("width", metavar="W", type=lambda t: _number(t, "W", True),
                   help="the window of the failed sensor's constant level, sensor units (> 0)")
    p.add_argument("level_q", metavar="LEVEL_Q", type=lambda t: _number(t, "LEVEL_Q", False),
                   help="the level's random walk per frame (>= 0; 0: no memory)")
    p.add_argument("sensor", metavar="SENSOR", nargs="?", default="VEL", choices=names.SENSORS,
                   help=f"the failed sensor ({', '.join(names.SENSORS)}; default VEL)")
    p.add_argument("start_up_s", metavar="START_UP_S", nargs="?", default=0.25,
                   type=lambda t: _number(t, "START_UP_S", False),
                   help="the start-up the file recommends, s (default 0.25)")
    a = p.parse_args(argv)
    s = load_schedule(p, a.schedule)
    j = names.SENSORS.index(a.sensor)
    nodes = []
    for n in s["nodes"]:
        nb = n["bank"]
        hyps = []
        for h in nb.hypotheses:
            w = np.array(h.uninformative_width, dtype=float)
            lq = np.array(h.uninformative_level_q, dtype=float)
            if a.sensor in h.name.split("+"):
                w[j], lq[j] = a.width, a.level_q
            hyps.append(core.HypothesisModel(name=h.name, phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a,
                                             uninformative_width=w, uninformative_level_q=lq))
        m = core.ModelBank(hyps, state_names=list(nb.state_names), input_names=list(nb.input_names),
                           measurement_names=list(nb.measurement_names), frame_rate_hz=nb.frame_rate_hz,
                           u_trim=nb.u_trim, z_trim=nb.z_trim, h_output=nb.h_output, mach=nb.mach, alt_ft=nb.alt_ft,
                           tuning=nb.tuning, p_min=nb.p_min, threshold=nb.threshold, dwell_s=nb.dwell_s,
                           metadata=nb.metadata)
        nodes.append((n["i_mach"], n["i_alt"], m, np.array(n["x_trim"]), n["adapt_reference"], n["layer"]))
    save_edited(s, nodes, a.out, f"{a.sensor} window {a.width}{' ft/s' if a.sensor == 'VEL' else ''}, level q {a.level_q}",
                start_up_s=a.start_up_s)
    return 0


if __name__ == "__main__":
    sys.exit(main())
