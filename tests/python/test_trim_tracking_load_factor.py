"""--trim-tracking-load-factor (loop/estimator_options.py; core keyword trim_load_factor,
cpp/f16mmae/trim_tracker.h; mmae-daemon's flag of the same name). The scaling itself is
checked against a hand computation in tests/cpp/test_trim_tracker_load_factor.cpp; here:

* "off" is the estimator without the option bit for bit, and "on" in level flight at the trim's
  AZ tracks the same AOA offset (n = the trim's AZ, within 1e-12 of 1 g for the tuned bank, so
  d1 = offset / n and n d1 the offset);
* the refusals: without --trim-tracking-steady and a value other than on/off, by name (the
  option table and the core);
* hil's daemon flags pass it as the daemon's flag.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import check

OPTIONS = {"trim_time_constant_s": 5.0, "trim_steady_g": 0.5, "trim_freeze_probability": 1.0}


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def _fly(bank, frames=320, **extra):
    aoa = list(bank.measurement_names).index("AOA")
    est = Estimator(bank, p_min=1e-9, **OPTIONS, **extra)
    z0, u0 = np.array(bank.z_trim), np.array(bank.u_trim)
    z0[aoa] += math.radians(0.05)
    dz = []
    for _ in range(frames):
        est.schedule(0.4, 20000.0)
        est.update(z0)
        dz.append(float(est.core_bank.trim_offset[1][aoa]))
        est.propagate(u0)
    return np.array(dz)


def test_off_is_bit_for_bit_and_on_tracks_the_level_offset(bank):
    base = _fly(bank)
    np.testing.assert_array_equal(_fly(bank, trim_load_factor="off"), base)
    az = float(np.array(bank.z_trim)[list(bank.measurement_names).index("AZ")])
    on = _fly(bank, trim_load_factor="on")
    assert base[-1] > 0.5 * math.radians(0.05)
    # n starts at 1 g and low-passes the trim's AZ; at AZ = 1 g both are the same low-pass
    np.testing.assert_allclose(on, base, rtol=abs(az - 1.0) * 4 + 1e-9, atol=1e-15)


def test_refusals_name_the_flag(bank):
    with pytest.raises(ValueError, match="--trim-tracking-load-factor applies with --trim-tracking-steady only"):
        check({"trim_time_constant_s": 30.0, "trim_load_factor": "on"})
    with pytest.raises(ValueError, match="--trim-tracking-load-factor 'yes' must be one of on, off"):
        check({"trim_time_constant_s": 30.0, "trim_steady_g": 0.1, "trim_load_factor": "yes"})
    from f16mmae import core
    with pytest.raises(ValueError, match="trim_load_factor must be 'on' or 'off', got 'yes'"):
        core.HierarchicalBank(bank, trim_time_constant_s=30.0, trim_steady_g=0.1, trim_load_factor="yes")
    with pytest.raises(ValueError, match="load_factor needs steady tracking"):
        core.HierarchicalBank(bank, trim_time_constant_s=30.0, trim_load_factor="on")


def test_the_daemon_gets_its_flag():
    from f16mmae.lcm.daemon import daemon_flags
    base = {"trim_time_constant_s": 30.0, "trim_steady_g": 0.1}
    flags = daemon_flags({**base, "trim_load_factor": "on"})
    i = flags.index("--trim-tracking-load-factor")
    assert flags[i + 1] == "on"
    assert "--trim-tracking-load-factor" not in daemon_flags(base)
