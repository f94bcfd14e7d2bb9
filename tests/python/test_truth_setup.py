"""Set-up once per flight condition: a pooled aircraft, restarted after other flights, flies
exactly as a freshly loaded and trimmed one; the pool trims each condition once per process
and gives simultaneous flights aircraft of their own."""
from __future__ import annotations

import numpy as np

from f16mmae.names import SIM_RATE_HZ
from f16mmae.truth import Scenario, TruthModel, aircraft, fly_raw, parse_fail, turbulence
from f16mmae.truth.pool import POOL
from f16mmae.truth.model import STATE_LOG

#: Recorded each step: the state, the forces, the mass and the engine.
WATCH = [p for _, p in STATE_LOG] + [
    "velocities/p-rad_sec", "velocities/q-rad_sec", "velocities/r-rad_sec", "forces/fbz-total-lbs",
    "forces/fby-total-lbs", "inertia/weight-lbs", "propulsion/engine/thrust-lbs",
    "propulsion/engine/n2", "atmosphere/total-wind-down-fps", "simulation/sim-time-sec"]


def _steps(fdm, n: int, level: str, u=None) -> np.ndarray:
    """JSBSim alone for n steps in turbulence ``level`` with the surfaces held (or set to u)."""
    turbulence.apply(fdm, level)
    if u is not None:
        aircraft.set_surfaces(fdm, u)
    out = []
    for _ in range(n):
        assert fdm.run()
        out.append([fdm[p] for p in WATCH])
    return np.array(out)


def test_a_restarted_aircraft_flies_as_a_freshly_trimmed_one():
    """Reference: load, trim, fly (the set-up every flight had before the pool).  Then one
    aircraft flies other flights -- other seed, severe turbulence, surfaces moved -- and is
    restarted: the reference flight comes out bit for bit."""
    n = 4 * SIM_RATE_HZ
    fresh = aircraft.load_fdm(seed=7, cxx=True)
    trim = aircraft.trim(fresh, 0.4, 20_000.0)
    want = _steps(fresh, n, "moderate")
    fdm = aircraft.load_fdm(seed=1, cxx=True)
    tp = aircraft.trim(fdm, 0.4, 20_000.0)
    start = aircraft.start_state(fdm)
    assert np.array_equal(tp.u_rad, trim.u_rad) and tp.throttle == trim.throttle
    for seed, level in ((3, "severe"), (4, "light")):
        aircraft.restart(fdm, tp, start, seed)
        _steps(fdm, n, level, tp.u_rad + np.radians([2, -1, 3, 1, -4]))
    aircraft.restart(fdm, tp, start, 7)
    got = _steps(fdm, n, "moderate")
    assert np.array_equal(got, want), np.abs(got - want).max(axis=0)
    assert np.abs(got[:, 1] - got[0, 1]).max() > 0.5  # the turbulence did act


def test_first_and_later_flights_of_a_condition_are_the_same():
    sc = Scenario(duration_s=2.0, seed=9, turbulence="light", failures=(parse_fail("RF@1.0:stuck"),),
                  feedback="raw")
    POOL.clear()
    trims = POOL.trims
    first = fly_raw(sc)[0].truth_log
    fly_raw(Scenario(duration_s=2.0, seed=10, turbulence="severe", failures=(parse_fail("LS@0.5:hardover"),),
                     feedback="raw"))
    again = fly_raw(sc)[0].truth_log
    for k in ("z", "state", "surface_rad"):
        assert np.array_equal(first[k], again[k]), k
    assert POOL.trims == trims + 1  # one load-and-trim for the three flights
    fly_raw(Scenario(mach=0.6, duration_s=0.5, feedback="raw"))
    fly_raw(Scenario(mach=0.6, duration_s=0.5, seed=2, feedback="raw"))
    assert POOL.trims == trims + 2


def test_simultaneous_flights_get_aircraft_of_their_own():
    a = TruthModel(Scenario(duration_s=0.5, seed=1))
    b = TruthModel(Scenario(duration_s=0.5, seed=2))
    assert a.fdm is not b.fdm
    za, zb = a.measure(), b.measure()
    assert not np.array_equal(za, zb)  # own noise and own aircraft
    a.close()
    b.close()
    c = TruthModel(Scenario(duration_s=0.5, seed=1))
    assert c.fdm is a.fdm or c.fdm is b.fdm  # a returned aircraft is reused
    assert np.array_equal(c.measure(), za)
    c.close()
