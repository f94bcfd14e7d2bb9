"""A copy of a bank whose failed sensors' level ranges W_j are set anew: the constant of the
uninformative density of a failed sensor's level (docs/results/failure_models.md measures it).

A cover sensor hypothesis reads a failed sensor j as an unknown level, uniform over W_j, plus
its noise: its first frame pays c_j = ln(sqrt(2 pi A_jj) / W_j) nats against a healthy reading
on the common footing, and its floor carries exp(c_j) (cpp/f16mmae/filter_bank.h). A cover
surface hypothesis pays nothing for its unknown position (a random-walk state its filter
learns, no range charged). `--width VEL=10.3` sets W_VEL = 10.3 (the sensor's units) in every
hypothesis whose VEL channel is uninformative; every filter is otherwise the bank's, bit for
bit, and the metadata gains "level_widths" (the bank it came from, the widths, the command):
a new content hash. `--occam VEL=-2.1` sets W_j so that c_j is that many nats in the
hypothesis that fails j alone (A_jj its own).

The design does the same from a tuning (``failed_sensor_level_width``, ``f16mmae design
--failed-sensor-level-width``, design/level_width.py), with a width derived from the model.

Run: .venv/bin/python tools/cover/level_width_bank.py IN.f16bank --occam VEL=-2.1 --out OUT.f16bank
"""
from __future__ import annotations

import argparse
import json
import math

from f16mmae import core


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("bank")
    ap.add_argument("--width", action="append", default=[], help="SENSOR=W, the level's range")
    ap.add_argument("--occam", action="append", default=[], help="SENSOR=C, c_j in nats (< 0)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    mb = core.load_bank(a.bank)
    meas = list(mb.measurement_names)
    names = list(mb.hypothesis_names)
    widths = {}
    for text in a.width + a.occam:
        sensor, _, value = text.partition("=")
        if sensor not in meas or sensor not in names:
            ap.error(f"{text!r}: {sensor!r} is not a sensor of the bank ({', '.join(meas)})")
        v = float(value)
        if text in a.width:
            if not v > 0.0:
                ap.error(f"--width {text!r}: W must be > 0")
            widths[sensor] = v
        else:
            if not v < 0.0:
                ap.error(f"--occam {text!r}: c must be < 0 nats (W above sqrt(2 pi A))")
            j = meas.index(sensor)
            a_jj = float(mb.hypotheses[names.index(sensor)].a[j, j])
            widths[sensor] = math.sqrt(2.0 * math.pi * a_jj) / math.exp(v)
    meta = json.loads(mb.metadata) if mb.metadata else {}
    meta["level_widths"] = {"from": str(mb.content_hash), "width": widths,
                            "command": "tools/cover/level_width_bank.py " + " ".join(
                                [f"--width {t}" for t in a.width] + [f"--occam {t}" for t in a.occam])}
    metadata = json.dumps(meta, sort_keys=True, separators=(",", ":"))
    hyps = []
    for h in mb.hypotheses:
        w = None if h.uninformative_width is None else [float(x) for x in h.uninformative_width]
        if w is not None and len(w):
            for sensor, width in widths.items():
                j = meas.index(sensor)
                if w[j] > 0.0:
                    w[j] = width
        hyps.append(core.HypothesisModel(name=h.name, phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a,
                                         uninformative_width=w if w else None,
                                         uninformative_level_q=h.uninformative_level_q))
    out = core.ModelBank(hyps, state_names=list(mb.state_names), input_names=list(mb.input_names),
                         measurement_names=meas, frame_rate_hz=mb.frame_rate_hz, u_trim=mb.u_trim,
                         z_trim=mb.z_trim, h_output=mb.h_output, mach=mb.mach, alt_ft=mb.alt_ft,
                         tuning=mb.tuning, p_min=mb.p_min, threshold=mb.threshold, dwell_s=mb.dwell_s,
                         metadata=metadata)
    core.save_bank(out, a.out)
    back = core.load_bank(a.out)
    print(f"wrote {a.out} ({str(back.content_hash)[:12]}): " +
          ", ".join(f"W_{s} = {w:.4g}" for s, w in widths.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
