"""The shipped schedule's trims where its stencils are cut (cpp/f16mmae/scheduled_filters.h:
plane_trims, row_trims, neighbour_trims, lift_trims, stabilator_trims), against independent answers:

* the truth model's own trim (JSBSim trimmed at the point): in a cell's uncovered half (Mach 0.32,
  29,000 ft; 0.365, 34,500 ft at the trimmable edge), in a cell missing three corners (0.345,
  31,500 ft) and in a cut stencil's cell (Mach 0.3453, 26,582 ft) the trims in force are near it,
  nearer than the schedule before round 37 (plane_trims, row_trims and lift_trims off);
* the truth model's stabilator trim past the trimmable edge (Mach 0.36, 34,000 ft; 0.37, 35,000 ft;
  the cell missing three corners at 0.345, 31,500 ft): the edge table's trims (stabilator_trims)
  are near it, where the covered triangle's plane is 0.008-0.012 rad off;
* a fresh choice: the row stencils a bank keeps from frame to frame give, bit for bit, the trims a
  bank choosing them afresh gives, along a path through the low-speed corner above 24,000 ft.
"""
from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.truth import aircraft


@pytest.fixture(scope="module")
def scheduled():
    _, _, bank = load_bank("scheduled")
    return bank


def _trims(bank, mach, alt_ft):
    """(z_trim, u_trim) in force at (mach, alt_ft), the air data's low-pass left behind."""
    bank.reset()
    for _ in range(3):
        bank.schedule(mach, alt_ft)
    return np.asarray(bank.z_trim).copy(), np.asarray(bank.u_trim).copy()


@pytest.mark.parametrize("mach, alt_ft, vel_fps, aoa_rad", [
    (0.32, 29000.0, 0.2, 0.0005),     # an uncovered half: the covered triangle's plane
    (0.365, 34500.0, 0.3, 0.0005),    # ... at the trimmable edge, alpha 0.34 rad
    (0.345, 31500.0, 0.3, 0.0005),    # three corners uncovered: the neighbours' planes
    (0.3453, 26582.0, 0.1, 0.0005),   # a cut stencil: row by row
])
def test_the_trims_in_force_are_near_the_truth_models_trim(scheduled, mach, alt_ft, vel_fps, aoa_rad):
    with contextlib.redirect_stdout(io.StringIO()):
        _, truth = aircraft.trimmed_fdm(mach, alt_ft)
    now = truth.z - _trims(core.HierarchicalBank(scheduled), mach, alt_ft)[0]
    before = truth.z - _trims(core.HierarchicalBank(scheduled, plane_trims=False, row_trims=False, lift_trims=False),
                              mach, alt_ft)[0]
    assert abs(now[0]) < vel_fps and abs(now[1]) < aoa_rad, now
    assert abs(now[0]) < abs(before[0]) and abs(now[1]) < abs(before[1]), (now, before)


@pytest.mark.parametrize("mach, alt_ft", [(0.36, 34000.0), (0.37, 35000.0), (0.345, 31500.0)])
def test_past_the_trimmable_edge_the_stabilator_trims_are_near_the_truth_models(scheduled, mach, alt_ft):
    with contextlib.redirect_stdout(io.StringIO()):
        _, truth = aircraft.trimmed_fdm(mach, alt_ft)
    now = truth.u_rad[:2] - _trims(core.HierarchicalBank(scheduled), mach, alt_ft)[1][:2]
    plane = truth.u_rad[:2] - _trims(core.HierarchicalBank(scheduled, stabilator_trims=False), mach, alt_ft)[1][:2]
    assert np.all(np.abs(now) < 0.001), now
    assert np.all(np.abs(plane) > 0.005), plane


def test_kept_row_stencils_give_a_fresh_choices_trims_bit_for_bit(scheduled):
    path = core.HierarchicalBank(scheduled, air_data_time_constant_s=0.0)
    fresh = core.HierarchicalBank(scheduled, air_data_time_constant_s=0.0)
    for x in np.linspace(0.0, 1.0, 1201):
        mach, alt_ft = 0.30 + 0.12 * x, 24000.0 + 11000.0 * ((7.0 * x) % 1.0)
        path.schedule(mach, alt_ft)
        fresh.reset()   # reset() chooses the stencils afresh
        fresh.schedule(mach, alt_ft)
        assert np.array_equal(path.z_trim, fresh.z_trim) and np.array_equal(path.u_trim, fresh.u_trim), (mach, alt_ft)
