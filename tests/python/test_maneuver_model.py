"""The maneuver model of the estimator (cpp/f16mmae/maneuver_kinematics.h, actuator_limits.h):
on a real maneuvering flight the roll-in's false declaration is gone with it and was there
without it; a failure injected during a turn is still isolated with it; the options reach the
core, the campaign configuration and the reproduce command, and bad values are named."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae.banks import bank_estimator_settings, load_bank
from f16mmae.campaign.engine.config import CampaignConfig, CampaignError
from f16mmae.campaign.engine.drilldown import reproduce_command
from f16mmae.cli.main import main
from f16mmae.loop.estimator import Estimator, core_arguments
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario
from f16mmae.truth.actuators import POSITION_LIMIT_RAD, RATE_LIMIT_RAD_S
from f16mmae.truth.failures import make_failure

MODEL = {"maneuver_kinematics": True, "actuator_limits": True, "maneuver_tempering_g": 0.1}


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def _replay(bank, frames, options):
    """The declarations of a fresh estimator with ``options`` over recorded (u, z, air data)."""
    est = Estimator(bank, **options)
    out = []
    for t, u, z, a in frames:
        est.schedule(*a)
        est.update(z)
        est.propagate(u)
        if est.last_declaration is not None:
            out.append((est.last_declaration, round(t, 6)))
    return out


def _frames(bank, scenario):
    frames = []
    fly(scenario, bank, feedback="raw", on_frame=lambda t, u, z, a: frames.append((t, np.array(u), np.array(z), a)))
    return frames


def test_roll_in_false_declaration_is_gone_with_the_model(bank):
    # A 30 deg turn from 2 s: the roll-in's saturated flaperon and rudder commands read as a
    # rudder failure to the bank as designed.
    frames = _frames(bank, Scenario(duration_s=6.0, seed=4, turbulence="light", maneuvers=("turn@2:bank=30deg",)))
    plain = _replay(bank, frames, {})   # the bank's evidence dwell: AY (32 nats) before the frame dwell's RUD
    assert plain and plain[0][0] == "AY" and 2.0 < plain[0][1] < 3.5, plain
    frame = _replay(bank, frames, {"dwell_nats": 0.0})
    assert frame and frame[0][0] == "RUD" and 2.0 < frame[0][1] < 3.5, frame
    assert _replay(bank, frames, MODEL) == []


def test_failure_during_a_turn_is_still_isolated(bank):
    sc = Scenario(duration_s=9.0, seed=4, turbulence="light", maneuvers=("turn@2:bank=30deg",),
                  failures=(make_failure("LS", 5.0, "complete"),))
    frames = _frames(bank, sc)
    decl = _replay(bank, frames, MODEL)
    assert decl and decl[0][0] == "LS" and 5.0 < decl[0][1] < 6.5, decl


def test_options_reach_the_core_the_config_and_the_reproduce_command(bank):
    args = core_arguments({**bank_estimator_settings(bank), **MODEL})
    assert "actuator_limits" not in args
    assert args["actuator_rate_limits_rad_s"] == list(RATE_LIMIT_RAD_S)
    assert args["actuator_position_limits_rad"] == list(POSITION_LIMIT_RAD)
    core_bank = Estimator(bank, **MODEL).core_bank
    assert core_bank.maneuver_kinematics and core_bank.actuator_limits
    cfg = CampaignConfig(estimator=MODEL)
    assert cfg.estimator_options() == MODEL
    cmd = reproduce_command(Scenario(duration_s=4.0, seed=3).to_dict(), "tuned", cfg.estimator_options())
    for flag in ("--maneuver-kinematics", "--actuator-limits", "--maneuver-tempering 0.1"):
        assert flag in cmd
    with pytest.raises(CampaignError, match="--maneuver-tempering -1"):
        CampaignConfig(estimator={"maneuver_tempering_g": -1.0}).check_common(dwell_window_s=8.0)


def test_bad_tempering_and_bank_without_lags_are_named(bank, capsys):
    assert main(["run", "--duration", "1", "--maneuver-tempering", "zero"]) != 0
    assert "--maneuver-tempering" in capsys.readouterr().err
    from f16mmae import core
    with pytest.raises(ValueError, match="rate_limit_rad_s and position_limit_rad need 5 values"):
        core.HierarchicalBank(bank, actuator_rate_limits_rad_s=[1.0], actuator_position_limits_rad=[1.0])
    with pytest.raises(ValueError, match="rate_limit_rad_s\\[2\\]"):
        core.HierarchicalBank(bank, actuator_rate_limits_rad_s=[1.0, 1.0, -1.0, 1.0, 1.0],
                              actuator_position_limits_rad=[1.0] * 5)
    with pytest.raises(ValueError, match="tempering_g"):
        core.HierarchicalBank(bank, maneuver_tempering_g=float("nan"))
