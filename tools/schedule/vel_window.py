"""Lab driver (not in the wheel), an experiment: the VEL (or SENSOR) hypotheses of every node as
a failed sensor reading an unknown constant level within W (sensor units; the cover model's
uniform prior, narrowed from the sensor's full range to the trim's uncertainty), its level a
random walk of LEVEL_Q per frame (hypotheses.py's `cover` density and level filter,
steady_state_filter.h).

    python tools/schedule/vel_window.py SCHEDULE OUT W LEVEL_Q [SENSOR [START_UP_S]]

Writes OUT: SCHEDULE with every node's SENSOR-failed hypotheses (SENSOR and SENSOR+c; default
VEL) so changed and the start-up START_UP_S recommended (default 0.25); nothing else changed.
Prints OUT and its content hash.  With W = 9.9 and LEVEL_Q = 2.5e-7 (1e-6 of VEL's noise
variance) these are the hypotheses of design/hypotheses.py's `constant` model for VEL, the
filter matrices being the `complete` model's (for AOA: W = 6 TRIM_SIGMA["AOA"], LEVEL_Q 1e-6
of AOA's noise variance)."""
import sys, json, numpy as np
from f16mmae import core
from f16mmae import names
src, out, W, q = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
sensor = sys.argv[5] if len(sys.argv) > 5 else "VEL"
start_up_s = float(sys.argv[6]) if len(sys.argv) > 6 else 0.25
j = names.SENSORS.index(sensor)
b = core.load_bank(src)
s = b.schedule
nodes = []
for n in s["nodes"]:
    nb = n["bank"]
    hyps = []
    for h in nb.hypotheses:
        w = np.array(h.uninformative_width, dtype=float)
        lq = np.array(h.uninformative_level_q, dtype=float)
        if sensor in h.name.split("+"):
            w[j], lq[j] = W, q
        hyps.append(core.HypothesisModel(name=h.name, phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a,
                                         uninformative_width=w, uninformative_level_q=lq))
    m = core.ModelBank(hyps, state_names=list(nb.state_names), input_names=list(nb.input_names),
                       measurement_names=list(nb.measurement_names), frame_rate_hz=nb.frame_rate_hz,
                       u_trim=nb.u_trim, z_trim=nb.z_trim, h_output=nb.h_output, mach=nb.mach, alt_ft=nb.alt_ft,
                       tuning=nb.tuning, p_min=nb.p_min, threshold=nb.threshold, dwell_s=nb.dwell_s,
                       metadata=nb.metadata)
    nodes.append((n["i_mach"], n["i_alt"], m, np.array(n["x_trim"]), n["adapt_reference"], n["layer"]))
meta = json.loads(s["metadata"]); meta["experiment"] = f"{sensor} window {W}{' ft/s' if sensor == 'VEL' else ''}, level q {q}"
h = core.save_schedule(list(s["mach"]), list(s["alt_ft"]), nodes, primary=s["primary"],
                       metadata=json.dumps(meta, sort_keys=True, separators=(",", ":")), path=out,
                       switch_state=s["switch_state"], switch_thresholds=list(s["switch_thresholds"]),
                       start_up_s=start_up_s)
print(out, h[:12])
