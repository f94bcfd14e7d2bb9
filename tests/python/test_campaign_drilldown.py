"""The reproduce command of a run: exact, complete, and refused for settings run cannot set."""
from __future__ import annotations

import json
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
    tracked = shlex.split(drilldown.reproduce_command(scenario(), "tuned", {"trim_time_constant_s": 30.0}))
    assert tracked[tracked.index("--trim-tracking") + 1] == "30.0"


def test_every_command_line_setting_is_written_back_as_the_command_line_reads_it():
    """A record holding every estimator setting gives a command whose options parse back to
    the same settings (the scheduled bank's mode and the adaptation's reference included)."""
    import argparse

    from f16mmae.cli.options import add_estimator_arguments, estimator_options_from_args

    settings = {"threshold": 0.95, "dwell_s": 0.5, "p_min": 1e-6, "adapt_turbulence": True, "adapt_reference": 0.76,
                "trim_time_constant_s": 30.0, "trim_freeze_probability": 0.2, "schedule_mode": "nearest",
                "maneuver_kinematics": True, "actuator_limits": True, "maneuver_tempering_g": 0.1,
                "level1_p_min": 1e-3, "maneuver_dwell_s": 1.5, "maneuver_dwell_hold_s": 30.0, "maneuver_dwell_g": 0.08,
                "maneuver_dwell_time_constant_s": 1.0, "maneuver_reference": 0.65}
    argv = shlex.split(drilldown.reproduce_command(scenario(), "scheduled", settings))
    p = argparse.ArgumentParser(allow_abbrev=False)   # else the scenario's --turbulence abbreviates --turbulence-banks
    add_estimator_arguments(p)
    args, _ = p.parse_known_args(argv[2:])
    assert estimator_options_from_args(args) == settings


def test_unknown_estimator_setting_is_refused():
    with pytest.raises(ValueError, match="valid: threshold, dwell_s, p_min, start_up_s, fresh_floor_levels, adapt_turbulence, "
                                         "adapt_reference"):
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


# -- the printed command flies the run again: one not-clean run of each campaign kind ------------------
def _fly_again(entry, records, out):
    from f16mmae.cli.main import main

    argv = shlex.split(entry["command"])
    assert argv[:2] == ["f16mmae", "run"]
    assert main(argv[1:] + ["--out", str(out)]) == 0
    flown = json.loads((out / "run.json").read_text())
    record = next(r for r in records if r["seed"] == entry["seed"] and r["declarations"] == entry["declarations"])
    assert flown["scenario"] == record["scenario"]
    assert flown["declarations"] == entry["declarations"]
    assert flown["final_hypothesis"] == entry["final_hypothesis"]


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["single", "dual", "envelope"])
def test_reproduce_command_gives_the_same_declarations(kind, tmp_path):
    from f16mmae.campaign.dual import DualCampaign, run_campaign as run_dual
    from f16mmae.campaign.engine.executor import InlineExecutor
    from f16mmae.campaign.envelope import EnvelopeCampaign, run_envelope
    from f16mmae.campaign.envelope.points import parse_mach_alt
    from f16mmae.campaign.single import SingleCampaign, run_campaign as run_single

    out = tmp_path / "campaign"
    # the untuned bank (the paper's floor) false-alarms often: these plans hold runs that are not clean
    if kind == "single":
        done = run_single(SingleCampaign(runs=2, cases=("NONE", "LS"), tuning="untuned", baseline=None,
                                         dither_scale=0.8, estimator={"p_min": 0.002}), out, InlineExecutor(),
                          show_progress=False, measure_cost=False)
    elif kind == "dual":
        done = run_dual(DualCampaign(runs=1, pairs=(("LF", "AZ"),), tuning="untuned"), out, InlineExecutor(),
                        show_progress=False)
    else:
        done = run_envelope(EnvelopeCampaign(runs=1, points=parse_mach_alt("0.42:21000"), cases=("NONE", "VEL")),
                            out, InlineExecutor(), show_progress=False)
    entries = done.summary["not_clean"]
    assert entries, f"the {kind} plan flew no run that went wrong"
    _fly_again(entries[0], done.records, tmp_path / "again")
    # the report opens on them, each with its command
    import html

    from f16mmae.report.page import render_report

    page = render_report(out).read_text()
    assert page.index("<h2>Runs that went wrong") < page.index("<h2>", page.index("<h1>") + 1) + 1
    assert html.escape(entries[0]["command"]) in page


@pytest.mark.slow
def test_report_header_names_the_settings_the_bank_carries(tmp_path):
    from f16mmae.campaign.engine.executor import InlineExecutor
    from f16mmae.campaign.single import SingleCampaign, run_campaign
    from f16mmae.report.page import render_report

    run_campaign(SingleCampaign(runs=1, cases=("NONE",), baseline=None, estimator={"dwell_s": 0.3}), tmp_path, InlineExecutor(),
                 show_progress=False, measure_cost=False)
    page = render_report(tmp_path).read_text()
    assert "core defaults" not in page
    assert "p_min=1e-09" in page and "bank: p_min, threshold" in page and "options: dwell_s" in page


def test_markdown_page_of_each_kind(tmp_path, capsys):
    """``f16mmae report DIR --markdown FILE`` from the golden summaries: command, totals, tables."""
    from pathlib import Path

    from f16mmae.cli.main import main

    golden = Path(__file__).with_name("golden")
    for kind, marker in (("single", "| LS |"), ("dual", "absolute (>= 90 % correct"), ("envelope", "| C1 |")):
        d = tmp_path / kind
        d.mkdir()
        summary = json.loads((golden / f"campaign_{kind}.json").read_text())["summary"]
        summary.update(command=f"f16mmae campaign {kind} --runs 1", code={"code": "git:x", "jsbsim": "1", "lcm": "1"},
                       codes_in_records={}, figures={})
        (d / "summary.json").write_text(json.dumps(summary))
        md = tmp_path / f"{kind}.md"
        assert main(["report", str(d), "--markdown", str(md)]) == 0
        text = md.read_text()
        assert f"f16mmae campaign {kind} --runs 1" in text and "evaluation seeds" in text and marker in text
        assert "pooled: correct" in text and "Runs that went wrong" in text
    assert main(["report", str(tmp_path / "single"), "--markdown", str(tmp_path / "no" / "x.md")]) == 2
    assert "existing directory" in capsys.readouterr().err


def test_a_run_flown_again_is_checked_against_its_records_declarations():
    from f16mmae.campaign.engine.drilldown import flies_as_recorded
    record = {"declarations": [{"hypothesis": "RS", "time_s": 574.765625}, {"hypothesis": "NONE", "time_s": 575.421875}]}
    assert flies_as_recorded(record, [dict(d) for d in record["declarations"]])
    assert not flies_as_recorded(record, [])                                   # declared nothing
    assert not flies_as_recorded(record, record["declarations"][:1])          # no back-out
    assert not flies_as_recorded(record, [{"hypothesis": "RS", "time_s": 574.78125}, record["declarations"][1]])
    assert flies_as_recorded({"declarations": []}, []) and flies_as_recorded({}, [])
