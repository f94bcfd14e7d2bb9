"""--trim-tracking-steady-measurements (loop/estimator_options.py): with steady trim tracking,
the measurements whose trim offsets are tracked (the core's trim_steady_measurements; AOA alone
without the option).

* the F-16 bank at its trim with VEL 0.5 ft/s and AOA 0.05 deg off, level air data: with
  "AOA,VEL" both offsets are the tracker's first-order low-pass recomputed here,
  dz_n = d (1 - (1 - a)^n); without the option (AOA) VEL's offset stays 0, its hypothesis rises
  to a declaration that freezes the tracker, and up to then AOA's offset is the same low-pass, bit
  for bit; lower case is read as the names;
* names that are not measurements, a name given twice and the option without
  --trim-tracking-steady are refused by name; mmae-daemon takes it (daemon_flags passes it on,
  the ready line names the measurements).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import check, parse_steady_measurements

RATE_HZ = 64.0
OPTIONS = {"trim_time_constant_s": 5.0, "trim_steady_g": 0.5, "trim_freeze_probability": 1.0}
OFF = {"VEL": 0.5, "AOA": math.radians(0.05)}


def _fly(bank, **extra):
    """The VEL and AOA offsets after each of 10 s of frames at the trim plus OFF."""
    names = list(bank.measurement_names)
    est = Estimator(bank, p_min=1e-9, **OPTIONS, **extra)
    z0, u0 = np.array(bank.z_trim), np.array(bank.u_trim)
    for name, d in OFF.items():
        z0[names.index(name)] += d
    out, frozen = [], []
    for _ in range(int(10 * RATE_HZ)):
        est.schedule(0.4, 20000.0)
        est.update(z0)
        dz = est.core_bank.trim_offset[1]
        out.append([float(dz[names.index("VEL")]), float(dz[names.index("AOA")])])
        frozen.append(bool(est.core_bank.trim_frozen))
        est.propagate(u0)
    return np.array(out), np.array(frozen)


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def test_the_named_measurements_are_tracked_as_the_low_pass(bank):
    dz, frozen = _fly(bank, trim_steady_measurements="aoa,vel")
    assert not frozen.any()
    a = 1.0 - math.exp(-1.0 / (RATE_HZ * OPTIONS["trim_time_constant_s"]))
    shape = 1.0 - (1.0 - a) ** np.arange(1, len(dz) + 1)
    np.testing.assert_allclose(dz[:, 0], OFF["VEL"] * shape, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(dz[:, 1], OFF["AOA"] * shape, rtol=1e-12, atol=1e-15)
    alone, alone_frozen = _fly(bank)
    assert not alone[:, 0].any()                          # the default: AOA alone
    # VEL's offset, untracked, raises its hypothesis to a declaration, which freezes the tracker;
    # up to then AOA's offset is the same, bit for bit
    first = int(np.argmax(alone_frozen))
    assert alone_frozen.any() and first > 64
    np.testing.assert_array_equal(alone[:first, 1], dz[:first, 1])


def test_the_names_are_read_and_refused_by_name():
    assert parse_steady_measurements(" aoa, VEL ,az") == ["AOA", "VEL", "AZ"]
    with pytest.raises(ValueError, match="--trim-tracking-steady-measurements: 'ALPHA' is not a measurement; "
                                         "valid: VEL, AOA, PIT, AZ, ROL, YAW, AY"):
        check({"trim_time_constant_s": 30.0, "trim_steady_g": 0.1, "trim_steady_measurements": "AOA,ALPHA"})
    with pytest.raises(ValueError, match="a measurement named twice in AOA,VEL,AOA"):
        check({"trim_time_constant_s": 30.0, "trim_steady_g": 0.1, "trim_steady_measurements": "AOA,VEL,AOA"})
    with pytest.raises(ValueError, match="--trim-tracking-steady-measurements applies with --trim-tracking-steady only"):
        check({"trim_time_constant_s": 30.0, "trim_steady_measurements": "AOA"})


def test_the_daemon_takes_the_measurements():
    """daemon_flags (hil) passes the names as given; the daemon's ready line names them."""
    from daemon_support import ready_line
    from f16mmae.banks import load_bank
    from f16mmae.lcm.daemon import daemon_flags
    flags = daemon_flags({"trim_time_constant_s": 30.0, "trim_steady_g": 0.1, "trim_steady_measurements": "aoa,VEL"})
    assert flags[-2:] == ("--trim-tracking-steady-measurements", "aoa,VEL")
    assert daemon_flags({"trim_time_constant_s": 30.0, "trim_steady_g": 0.1,
                         "trim_steady_measurements": ["AOA", "AZ"]})[-1] == "AOA,AZ"
    assert "steady 0.1 g on AOA,VEL)" in ready_line("--bank", str(load_bank("tuned")[1]), *flags)
