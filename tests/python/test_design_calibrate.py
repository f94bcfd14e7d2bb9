"""The shipped ``tuned`` tuning is reproducible: re-running the documented two-stage
calibration (design/calibrate.py, convergence.py: measurements against the nonlinear truth)
gives the same file; stage 1 makes the NONE filter consistent, stage 2 improves the bank's
probability convergence."""
from __future__ import annotations

import numpy as np

from f16mmae import names
from f16mmae.design import calibrate
from f16mmae.design.tuning import TUNINGS_DIR


def test_tuned_toml_is_what_the_calibration_produces():
    tun, hist, conv = calibrate.run_calibration()
    text = calibrate.render_toml(tun, hist[0], hist[-2], hist[-1], conv)
    assert text == (TUNINGS_DIR / "tuned.toml").read_text(), (
        "tunings/tuned.toml is stale (the truth model changed?): run "
        "'python -m f16mmae.design.calibrate --write'")
    untuned, stage1 = hist[0], hist[-2]
    assert untuned.nis_mean > 2 * names.NZ  # the untuned design is clearly mismatched
    assert abs(stage1.nis_mean - names.NZ) < 0.1 * names.NZ
    assert np.all(stage1.var_over_a < 1.15) and np.all(stage1.var_over_a > 0.5)
    kept = [r for r in conv if r["kept"]]
    assert kept[-1]["J"] >= kept[0]["J"]
