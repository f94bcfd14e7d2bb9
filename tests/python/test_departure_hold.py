"""The departure hold at the dual level (cpp/f16mmae/hierarchical_bank.h, ``--departure-hold``)
in closed loop on the shipped bank: a 25-deg stabilator hardover departs the aircraft after LS
is declared; without the hold the level-1 bank then declares duals the flight does not have,
with it LS stays the answer.  The hold's condition is recomputed here from the measurements
the estimator was given (numpy, the header's bounds), never from the truth."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.design import bank as design_bank
from f16mmae.loop.flight import fly
from f16mmae.truth.failures import parse_fail
from f16mmae.truth.scenario import Scenario

pytestmark = pytest.mark.slow

AOA_BOUND_RAD = np.radians(5.0)
RATE_BOUND_RAD_S = np.radians(10.0)
HOLD_FRAMES = 64   # 1 s at 64 Hz


@pytest.fixture(scope="module")
def tuned():
    return core.load_bank(design_bank.nominal_bank_path("tuned"))


def _fly(mb, fail: str | None, hold: str):
    failures = (parse_fail(fail),) if fail else ()
    sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence="light", seed=7000, duration_s=8.0, failures=failures)
    return fly(sc, mb, record_series=True, estimator_options={"departure_hold": hold})


def _outside(mb, z: np.ndarray) -> np.ndarray:
    """Frames whose readings leave the linearization (the header's rule, no channel left out:
    the first failure here is a surface)."""
    dz = z - np.asarray(mb.z_trim)
    s = list(names.SENSORS)
    rates = np.abs(dz[:, [s.index("PIT"), s.index("ROL"), s.index("YAW")]]).max(axis=1)
    return (np.abs(dz[:, s.index("AOA")]) > AOA_BOUND_RAD) | (rates > RATE_BOUND_RAD_S)


def test_stabilator_hardover_keeps_the_first_declaration_through_the_departure(tuned):
    off = _fly(tuned, "LS@3:hardover", "off")
    on = _fly(tuned, "LS@3:hardover", "on")
    seen_off = [d["hypothesis"] for d in off.declarations]
    assert seen_off[0] == "LS" and len(seen_off) >= 2 and all("+" in h for h in seen_off[1:]), seen_off
    assert [d["hypothesis"] for d in on.declarations] == ["LS"]
    assert on.declarations[0]["time_s"] == off.declarations[0]["time_s"]
    # every dual the unheld bank declared came within the hold of a frame outside the linearization
    outside = _outside(tuned, off.series["z"])
    for d in off.declarations[1:]:
        i = int(round(d["time_s"] / off.frame_dt_s))
        assert outside[max(0, i - HOLD_FRAMES):i + 1].any(), d
    # and up to the first declaration the two flights are the same
    i0 = int(round(on.declarations[0]["time_s"] / on.frame_dt_s))
    assert np.array_equal(on.probabilities[:i0 + 1], off.probabilities[:i0 + 1], equal_nan=True)


@pytest.mark.parametrize("fail", [None, "LS@3:complete", "LF@3:stuck"])
def test_flights_inside_the_linearization_are_untouched(tuned, fail):
    off = _fly(tuned, fail, "off")
    on = _fly(tuned, fail, "on")
    assert not _outside(tuned, on.series["z"]).any()
    assert on.declarations == off.declarations
    assert np.array_equal(on.probabilities, off.probabilities, equal_nan=True)


def test_departure_hold_takes_on_or_off(tuned):
    with pytest.raises(ValueError, match="departure_hold must be 'on' or 'off'"):
        core.HierarchicalBank(tuned, departure_hold="yes")
