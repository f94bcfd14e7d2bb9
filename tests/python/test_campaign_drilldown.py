"""The reproduce command of a run: exact, complete, and refused for settings run cannot set."""
from __future__ import annotations

import shlex

import pytest

from f16mmae.campaign.engine import drilldown


def scenario(**kw):
    base = {"seed": 123456789, "duration_s": 8.0, "turbulence": "light", "mach": 0.385, "alt_ft": 19500.0,
            "feedback": "mmae", "dither": {"enabled": True},
            "failures": [{"name": "LS", "time_s": 3.0, "mode": "complete"},
                         {"name": "AZ", "time_s": 5.1, "mode": "bias", "value": 0.2}]}
    base.update(kw)
    return base


def test_command_names_every_field():
    cmd = drilldown.reproduce_command(scenario(), "tuned", {"p_min": 1e-3}, dither_scale=0.1 + 0.2)
    argv = shlex.split(cmd)
    assert argv[:2] == ["f16mmae", "run"]
    opts = dict(zip(argv[2::2], argv[3::2]))
    assert opts["--seed"] == "123456789" and opts["--mach"] == "0.385" and opts["--alt-ft"] == "19500.0"
    assert float(opts["--dither-scale"]) == 0.1 + 0.2  # repr keeps every bit
    assert [a for i, a in enumerate(argv) if argv[i - 1] == "--fail"] == ["LS@3.0:complete", "AZ@5.1:bias=0.2"]
    assert opts["--bank"] == "tuned" and opts["--p-min"] == "0.001"
    assert "--no-dither" in drilldown.reproduce_command(scenario(dither={"enabled": False}), "tuned", {})


def test_unknown_estimator_setting_is_refused():
    with pytest.raises(ValueError, match="valid: threshold, dwell_s, p_min"):
        drilldown.reproduce_command(scenario(), "tuned", {"gain": 2.0})


def test_not_clean_lists_misses_and_flags():
    recs = [{"case": "LS", "run_index": 0, "seed": 5, "outcome": "correct", "false_alarm": False,
             "transient_wrong": False, "final_hypothesis": "LS", "declarations": []},
            {"case": "LS", "run_index": 1, "seed": 6, "outcome": "correct", "false_alarm": False,
             "transient_wrong": True, "final_hypothesis": "LS", "declarations": [{"hypothesis": "RS", "time_s": 3.2}]},
            {"case": "NONE", "run_index": 0, "seed": 7, "outcome": "wrong", "false_alarm": True,
             "transient_wrong": False, "final_hypothesis": "LF", "declarations": [{"hypothesis": "LF", "time_s": 4.0}]}]
    out = drilldown.not_clean(recs, command=lambda r: f"cmd {r['seed']}", label=lambda r: {"case": r["case"]})
    assert [(o["case"], o["seed"], o["flags"], o["command"]) for o in out] == [
        ("LS", 6, ["transient_wrong"], "cmd 6"), ("NONE", 7, ["false_alarm"], "cmd 7")]
