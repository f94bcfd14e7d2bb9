"""The angle-of-attack tempering's trim knee (cpp/f16mmae/maneuver_kinematics.h): the reference
shrinks as (a_k / alpha0)^3 above a trim alpha a_k, alpha0 the trim in force's. Replayed over one
recorded flight in moderate air, a knee just above the bank's own trim alpha changes nothing, bit
for bit, and one just below it changes the probabilities; so the core reads the trim's angle of
attack and nothing else. The options reach the core and the reproduce command, and a knee
without the alpha term is refused by name."""
from __future__ import annotations

import math

import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.campaign.engine.config import CampaignConfig, CampaignError
from f16mmae.campaign.engine.drilldown import reproduce_command
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario

ALPHA = {"maneuver_tempering_alpha_deg": 1.0, "maneuver_tempering_alpha_deadband_deg": 0.25}


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


@pytest.fixture(scope="module")
def frames(bank):
    out = []
    fly(Scenario(duration_s=6.0, seed=11, turbulence="moderate"), bank, feedback="raw",
        on_frame=lambda t, u, z, a: out.append((np.array(u), np.array(z), a)))
    return out


def _probabilities(bank, frames, **options):
    est = Estimator(bank, **ALPHA, **options)
    rows = []
    for u, z, a in frames:
        est.schedule(*a)
        est.update(z)
        est.propagate(u)
        rows.append(np.array(est.probabilities))
    return np.array(rows)


def test_knee_reads_the_trims_angle_of_attack(bank, frames):
    alpha0 = math.degrees(bank.z_trim[bank.measurement_names.index("AOA")])
    plain = _probabilities(bank, frames)
    above = _probabilities(bank, frames, maneuver_tempering_alpha_trim_deg=alpha0 * 1.001)
    below = _probabilities(bank, frames, maneuver_tempering_alpha_trim_deg=alpha0 * 0.98)
    assert np.array_equal(plain, above)
    assert np.max(np.abs(below - plain)) > 1e-6   # (0.98)^3: the reference 6 % smaller


def test_knee_reaches_the_core_and_the_reproduce_command_and_bad_ones_are_named(bank):
    options = {**ALPHA, "maneuver_tempering_alpha_trim_deg": 8.5}
    cfg = CampaignConfig(estimator=options)
    assert cfg.estimator_options() == options
    cmd = reproduce_command(Scenario(duration_s=4.0, seed=3).to_dict(), "tuned", cfg.estimator_options())
    assert "--maneuver-tempering-alpha-trim 8.5" in cmd
    with pytest.raises(CampaignError, match="--maneuver-tempering-alpha-trim"):
        CampaignConfig(estimator={**ALPHA, "maneuver_tempering_alpha_trim_deg": 91.0}).check_common(dwell_window_s=8.0)
    from f16mmae import core
    with pytest.raises(ValueError, match="tempering_alpha_trim_deg applies with tempering_alpha_deg > 0 only"):
        core.HierarchicalBank(bank, maneuver_tempering_alpha_trim_deg=8.5)
