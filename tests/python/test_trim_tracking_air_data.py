"""--trim-tracking-steady-air-data (loop/estimator_options.py, loop/estimator.core_arguments):
with steady trim tracking, "off" lets the air data's climb and Mach rates no longer freeze it.

* the F-16 bank at its trim with the angle of attack 0.05 deg off, handed air data that climb
  at 50 ft/s and then speed up at 0.005 Mach/s: with "off" no frame freezes and the AOA offset
  is the tracker's first-order low-pass recomputed here, dz_n = 0.05 deg (1 - (1 - a)^n); with
  "on" (and without the option) the climb freezes it, the same estimate bit for bit;
* the option maps to the core's infinite climb and Mach limits, and only to them;
* it is refused without --trim-tracking-steady and with a value other than on/off, by name.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator, core_arguments
from f16mmae.loop.estimator_options import check

RATE_HZ = 64.0
OPTIONS = {"trim_time_constant_s": 5.0, "trim_steady_g": 0.5, "trim_freeze_probability": 1.0}


def _fly(bank, **extra):
    """Offsets of AOA after each frame and whether the tracker was frozen, over 32 s of air data
    holding, climbing at 50 ft/s (5-15 s), holding, and speeding up at 0.005 Mach/s (20-25 s)."""
    aoa = list(bank.measurement_names).index("AOA")
    est = Estimator(bank, p_min=1e-9, **OPTIONS, **extra)
    z0, u0 = np.array(bank.z_trim), np.array(bank.u_trim)
    z0[aoa] += math.radians(0.05)
    h, m = 20000.0, 0.4
    dz, frozen = [], []
    for i in range(int(32 * RATE_HZ)):
        t = i / RATE_HZ
        h += 50.0 / RATE_HZ if 5.0 <= t < 15.0 else 0.0
        m += 0.005 / RATE_HZ if 20.0 <= t < 25.0 else 0.0
        est.schedule(m, h)
        est.update(z0)
        dz.append(float(est.core_bank.trim_offset[1][aoa]))
        frozen.append(bool(est.core_bank.trim_frozen))
        est.propagate(u0)
    return np.array(dz), np.array(frozen)


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def test_off_tracks_through_the_climb_and_the_speed_change_as_the_low_pass(bank):
    dz, frozen = _fly(bank, trim_steady_air_data="off")
    assert not frozen.any()
    a = 1.0 - math.exp(-1.0 / (RATE_HZ * OPTIONS["trim_time_constant_s"]))
    n = np.arange(1, len(dz) + 1)
    np.testing.assert_allclose(dz, math.radians(0.05) * (1.0 - (1.0 - a) ** n), rtol=1e-12, atol=1e-15)


def test_on_is_the_air_data_gate_bit_for_bit(bank):
    dz_on, frozen_on = _fly(bank, trim_steady_air_data="on")
    dz_default, frozen_default = _fly(bank)
    np.testing.assert_array_equal(dz_on, dz_default)
    np.testing.assert_array_equal(frozen_on, frozen_default)
    climb = slice(int(8 * RATE_HZ), int(15 * RATE_HZ))
    assert frozen_on[climb].all() and not frozen_on[:int(5 * RATE_HZ)].any()
    dz_off, _ = _fly(bank, trim_steady_air_data="off")
    assert dz_on[-1] < dz_off[-1]        # frozen for a third of the flight, it lags


def test_the_core_arguments_of_the_option():
    off = core_arguments({"trim_steady_air_data": "off", "trim_steady_g": 0.1})
    assert off == {"trim_steady_g": 0.1, "trim_steady_climb_ft_s": math.inf, "trim_steady_mach_per_s": math.inf}
    assert core_arguments({"trim_steady_air_data": "on", "trim_steady_g": 0.1}) == {"trim_steady_g": 0.1}


def test_refusals_name_the_flag():
    with pytest.raises(ValueError, match="--trim-tracking-steady-air-data applies with --trim-tracking-steady only"):
        check({"trim_time_constant_s": 30.0, "trim_steady_air_data": "off"})
    with pytest.raises(ValueError, match="--trim-tracking-steady-air-data 'no' must be one of on, off"):
        check({"trim_time_constant_s": 30.0, "trim_steady_g": 0.1, "trim_steady_air_data": "no"})


def test_the_daemon_takes_the_air_data_gate():
    """daemon_flags (hil) passes "off" as --trim-tracking-steady-air-data off, which the daemon's
    ready line names; "on" is the daemon's own behaviour and passes no flag."""
    from daemon_support import ready_line
    from f16mmae.banks import load_bank
    from f16mmae.lcm.daemon import daemon_flags
    base = {"trim_time_constant_s": 30.0, "trim_steady_g": 0.1}
    assert daemon_flags({**base, "trim_steady_air_data": "on"}) == daemon_flags(base)
    flags = daemon_flags({**base, "trim_steady_air_data": "off"})
    assert flags[-2:] == ("--trim-tracking-steady-air-data", "off") and flags.count("off") == 1
    bank = str(load_bank("tuned")[1])
    assert "steady 0.1 g, air-data rates off)" in ready_line("--bank", bank, *flags)
    assert "air-data rates" not in ready_line("--bank", bank, *daemon_flags(base))
