"""Property tests (Hypothesis) of the estimator's invariants through the binding, on the shipped
tuned bank (``core.HierarchicalBank``, the estimator that flies and that mmae-daemon runs):

- after every frame the probabilities of the hypotheses on line are finite, each >= p_min,
  and sum to 1 -- whatever the frames hold: ordinary values, huge ones (1e308), NaN, +-Inf;
- every frame with a non-finite entry is rejected and counted (``rejected_frames``: an update
  with a non-finite z, a propagate with a non-finite u); with moderate finite values nothing
  else is rejected, so the count is exact;
- the declared hypothesis is always one of the bank's.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from f16mmae import core
from f16mmae.design import bank as design_bank

BANK = core.load_bank(design_bank.nominal_bank_path("tuned"))
SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])

HOSTILE = st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e308, 1e150, -1e150, 5e-324])


def frames(hostile: bool):
    """Lists of (z offset from trim (7), u offset from trim (5)) frames: moderate values, and
    either hostile values anywhere or whole frames spoiled by one NaN."""
    moderate = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False, allow_infinity=False)
    v = st.one_of(moderate, HOSTILE) if hostile else moderate

    def spoil(vec, at):  # at: index to set NaN, or None
        return [math.nan if i == at else x for i, x in enumerate(vec)]

    frame = st.tuples(st.lists(v, min_size=7, max_size=7), st.lists(v, min_size=5, max_size=5),
                      st.one_of(st.none(), st.integers(0, 6)), st.one_of(st.none(), st.integers(0, 4)))
    return st.lists(frame.map(lambda f: (spoil(f[0], f[2]), spoil(f[1], f[3]))), min_size=1, max_size=40)


def fly(frame_list):
    """Runs the frames; checks the invariants after each; returns (bank, non-finite frames)."""
    est = core.HierarchicalBank(BANK, **BANK.estimator_settings)
    p_min = est.p_min
    non_finite = 0
    for dz, du in frame_list:
        z = BANK.z_trim + np.array(dz)
        u = BANK.u_trim + np.array(du)
        non_finite += int(not np.isfinite(z).all()) + int(not np.isfinite(u).all())
        est.update(z)
        est.propagate(u)
        p = np.asarray(est.probabilities)
        assert np.isfinite(p).all(), p
        assert (p >= p_min * (1 - 1e-12)).all(), (p.min(), p_min)
        assert abs(p.sum() - 1.0) < 1e-9, p.sum()
        assert est.declared in BANK.hypothesis_names
    return est, non_finite


@SETTINGS
@given(frames(hostile=True))
def test_probabilities_stay_finite_floored_and_normalised_under_hostile_frames(frame_list):
    est, non_finite = fly(frame_list)
    # every non-finite frame is counted; a finite but huge one may be too (its results overflow)
    assert non_finite <= est.rejected_frames <= 2 * len(frame_list)


@SETTINGS
@given(frames(hostile=False))
def test_exactly_the_non_finite_frames_are_rejected(frame_list):
    est, non_finite = fly(frame_list)
    assert est.rejected_frames == non_finite


def test_a_rejected_frame_changes_nothing():
    est = core.HierarchicalBank(BANK, **BANK.estimator_settings)
    est.update(BANK.z_trim + 0.01)
    est.propagate(BANK.u_trim)
    before = (np.array(est.probabilities), np.array(est.z_hat), est.rejected_frames)
    est.update(np.full(7, math.nan))
    assert est.rejected_frames == before[2] + 1
    np.testing.assert_array_equal(est.probabilities, before[0])
    np.testing.assert_array_equal(est.z_hat, before[1])


@pytest.mark.parametrize("dwell_s", [3.4e7, 61.0, -1.0, math.nan, math.inf])
def test_a_dwell_out_of_range_is_refused_where_it_enters_the_core(dwell_s):
    """Issue 16: dwell 3.4e7 s once wrapped to dwell_frames = INT_MIN and declared at once."""
    with pytest.raises(ValueError, match=r"dwell_s must be in \[0, 60\] s, got"):
        core.HierarchicalBank(BANK, dwell_s=dwell_s)
    assert core.HierarchicalBank(BANK, dwell_s=60.0).dwell_frames == 3840
