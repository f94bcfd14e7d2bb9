"""The detectability campaign: run scoring and summary arithmetic against hand-made records and
hand-computed intervals, the plan's common seeds, bad options refused by name, and a tiny
campaign end to end on the REAL truth model and estimator (CLI, figures, report, Markdown, resume)."""
from __future__ import annotations

import json
import math

import pytest

from f16mmae.banks import load_bank
from f16mmae.campaign.detectability import (DetectabilityCampaign, plan, score_detection, sigma_of, summarize,
                                            summarize_point, truth_value)
from f16mmae.campaign.engine.config import CampaignError
from f16mmae.campaign.engine.failure_runs import failure_offset
from f16mmae.campaign.engine.store import ResultsStore
from f16mmae.cli.main import main


def test_score_detection_by_hand():
    decl = [{"hypothesis": "AZ", "time_s": 3.2}, {"hypothesis": "AOA", "time_s": 3.9},
            {"hypothesis": "NONE", "time_s": 5.0}]
    s = score_detection("AOA", 3.0, decl, 8.0)
    assert s["detected"] and s["any_declared"] and not s["false_alarm"]
    assert s["latency_s"] == pytest.approx(0.9) and s["final_hypothesis"] == "NONE"
    assert s["outcome"] == "missed" and s["transient_wrong"] and s["failure_free_s"] == 3.0
    # a mis-isolation: something declared, never the failed sensor
    s = score_detection("VEL", 3.0, decl, 8.0)
    assert (s["detected"], s["any_declared"], s["latency_s"]) == (False, True, None)
    # declared before the onset only: a false alarm, not a detection
    s = score_detection("AZ", 4.0, decl[:2], 8.0)
    assert (s["detected"], s["any_declared"], s["false_alarm"], s["false_declarations"]) == (False, False, True, 2)
    assert score_detection("LS", 3.0, [], 8.0)["outcome"] == "missed"


def _rec(detected, any_declared, latency, false_alarm=False):
    return {"detected": detected, "any_declared": any_declared, "latency_s": latency, "false_alarm": false_alarm}


def test_summary_point_rates_and_intervals_by_hand():
    recs = [_rec(True, True, 0.4), _rec(False, True, None)]
    p = summarize_point(3.0, 0.0052, recs)
    assert p["runs"] == 2 and p["latency_median_s"] == pytest.approx(0.4)
    d = p["detected"]
    assert (d["count"], d["fraction"]) == (1, 0.5)
    # 1 of 2, exact interval: Beta(1,2) CDF 1-(1-x)^2 = 0.025 and Beta(2,1) CDF x^2 = 0.975
    lo, hi = d["ci95"]["clopper_pearson"]
    assert lo == pytest.approx(1 - math.sqrt(0.975), abs=1e-6) and hi == pytest.approx(math.sqrt(0.975), abs=1e-6)
    a = p["any_declared"]
    # 2 of 2: lower bound 0.025^(1/2)
    assert a["count"] == 2 and a["ci95"]["clopper_pearson"] == [pytest.approx(math.sqrt(0.025), abs=1e-6), 1.0]
    assert p["false_alarm"]["count"] == 0 and p["declared_instead"] == {}
    # the hypotheses declared instead: each run's first other one after the onset, most frequent
    # first, ties by name whatever the order of the records
    other = [{"component": "AOA", "failure_time_s": 3.0, "declarations": d, **_rec(False, True, None)} for d in (
        [{"hypothesis": "RF", "time_s": 3.1}, {"hypothesis": "AZ", "time_s": 3.5}],
        [{"hypothesis": "AZ", "time_s": 2.0}, {"hypothesis": "VEL", "time_s": 3.3}],
        [{"hypothesis": "NONE", "time_s": 3.2}, {"hypothesis": "AZ", "time_s": 3.4}],
        [{"hypothesis": "LS", "time_s": 3.0}], [{"hypothesis": "AOA", "time_s": 3.6}])]
    for recs in (other, other[::-1]):
        assert list(summarize_point(1.0, 0.0, recs)["declared_instead"].items()) == [("AZ", 1), ("LS", 1), ("RF", 1)]


def test_truth_values_follow_the_sensor_sigma_and_the_lost_fraction():
    assert sigma_of("AOA") == pytest.approx(0.1 * math.pi / 180)
    assert truth_value("bias", "AOA", 3.0) == pytest.approx(0.3 * math.pi / 180)
    assert truth_value("drift", "VEL", 2.0) == pytest.approx(1.0)  # 2 x 0.5 ft/s per s
    assert truth_value("loss", "LS", 0.25) == pytest.approx(0.75)  # the truth's remaining fraction
    assert truth_value("loss", "LS", 1.0) == 0.0


def test_summary_groups_records_by_family_component_and_size():
    cfg = DetectabilityCampaign(runs=2, components=("AZ", "RUD"), sizes=(1.0, 5.0), rates=(2.0,), losses=(0.5,))
    _, _, bank = load_bank("tuned")
    hits = {("bias", 1.0): 0, ("bias", 5.0): 2, ("drift", 2.0): 1, ("loss", 0.5): 2}
    recs = []
    for spec in plan(cfg, "tuned", bank):  # hand-made declarations on the planned runs
        comp, t_f = spec["component"], cfg.failure_time_s
        if spec["run_index"] < hits[spec["family"], spec["size"]]:
            decl = [{"hypothesis": comp, "time_s": t_f + 0.5}]
        else:  # a missed bias is mis-isolated as AOA, a missed drift declares nothing
            decl = [{"hypothesis": "AOA", "time_s": t_f + 0.2}] if spec["family"] == "bias" else []
        recs.append({**spec, "failure_time_s": t_f, "declarations": decl,
                     **score_detection(comp, t_f, decl, cfg.duration_s)})
    s = summarize(cfg, "tuned", bank, recs)
    assert list(s["families"]) == ["bias", "drift", "loss"]
    bias = s["families"]["bias"]["components"]
    assert [c["component"] for c in bias] == ["AZ"]  # RUD is no sensor
    assert [p["detected"]["count"] for p in bias[0]["points"]] == [0, 2]
    assert bias[0]["points"][1]["value"] == pytest.approx(0.05)  # 5 x 0.01 g
    assert bias[0]["points"][1]["latency_median_s"] == pytest.approx(0.5)
    assert s["families"]["drift"]["components"][0]["points"][0]["detected"]["fraction"] == 0.5
    loss = s["families"]["loss"]["components"]
    assert [c["component"] for c in loss] == ["RUD"] and loss[0]["points"][0]["value"] == 0.5
    assert s["goals_met"] and s["sigma"]["AZ"] == 0.01
    assert bias[0]["points"][0]["declared_instead"] == {"AOA": 2} and bias[0]["points"][1]["declared_instead"] == {}
    assert bias[0]["points"][0]["any_declared"]["count"] == 2
    # the runs that declared a wrong failure are listed with the command that flies each again;
    # the drift run that merely missed is a point of the curve
    assert [(r["family"], r["size"], r["run_index"]) for r in s["not_clean"]] == [("bias", 1.0, 0), ("bias", 1.0, 1)]
    assert "--fail AZ@3.0:bias=0.01 " in s["not_clean"][0]["command"]
    assert s["totals"]["correct"]["count"] == 5 and s["false_declarations_per_hour"]["events"] == 0


def test_plan_flies_run_n_on_one_seed_at_every_size_and_family():
    cfg = DetectabilityCampaign(runs=3, components=("PIT", "LF"), sizes=(1.0, 10.0), rates=(1.0,), losses=(0.5, 1.0))
    _, _, bank = load_bank("tuned")
    specs = plan(cfg, "tuned", bank)
    assert len(specs) == 3 * (2 + 1) + 3 * 2  # PIT: bias x2 + drift x1; LF: loss x2
    assert len({s["run_key"] for s in specs}) == len(specs)
    for comp in ("PIT", "LF"):
        for n in range(3):
            seeds = {s["seed"] for s in specs if s["component"] == comp and s["run_index"] == n}
            assert len(seeds) == 1
    assert len({s["seed"] for s in specs if s["component"] == "PIT"}) == 3
    f = next(s for s in specs if s["family"] == "drift")["scenario"]["failures"][0]
    assert f["mode"] == "drift" and f["value"] == pytest.approx(sigma_of("PIT"))


def test_the_failure_jitter_shifts_a_run_s_failure_and_end_alike_at_every_size():
    cfg = DetectabilityCampaign(runs=2, components=("AOA",), sizes=(1.0, 10.0), rates=(1.0,), failure_time_s=4.0,
                                duration_s=9.0, failure_jitter_s=1.5).validate()
    _, _, bank = load_bank("tuned")
    specs = plan(cfg, "tuned", bank)
    assert len(specs) == 2 * 3
    for spec in specs:
        offset = failure_offset(spec["seed"], 1.5)   # the single-failure campaign's offset of that seed
        assert 0.0 < offset < 1.5
        assert spec["scenario"]["failures"][0]["time_s"] == pytest.approx(4.0 + offset)
        assert spec["scenario"]["duration_s"] == pytest.approx(9.0 + offset)
    for n in range(2):   # one offset per run at every size and family
        assert len({s["scenario"]["failures"][0]["time_s"] for s in specs if s["run_index"] == n}) == 1
    plain = plan(DetectabilityCampaign(runs=2, components=("AOA",), sizes=(1.0, 10.0), rates=(1.0,)), "tuned", bank)
    assert {s["scenario"]["failures"][0]["time_s"] for s in plain} == {3.0}


@pytest.mark.parametrize("kwargs, expected", [
    (dict(failure_jitter_s=61.0), "--failure-jitter 61 must lie in [0, 60] s"),
    (dict(sizes=()), "--sizes needs 1 to 20 values, got 0"),
    (dict(losses=(0.5, 1.5)), "--losses value 1.5 must lie in (0, 1]"),
    (dict(rates=(0.0,)), "--rates value 0.0 must lie in (0, 1000]"),
    (dict(components=("LS", "XX")), "unknown component(s) XX"),
    (dict(failure_time_s=9.0), "the failure time 9.0 s must lie inside the flight"),
])
def test_config_refuses_bad_values_by_name(kwargs, expected):
    with pytest.raises(CampaignError) as exc:
        DetectabilityCampaign(**kwargs).validate()
    assert expected in str(exc.value)


@pytest.mark.parametrize("argv, expected", [
    (["--sizes", "0"], "--sizes '0' must be > 0.0"),
    (["--sizes", "1,x"], "--sizes 'x' is not a number"),
    (["--sizes", "1,1"], "--sizes '1,1' lists a value twice"),
    (["--rates", "2000"], "--rates '2000' must be <= 1000.0"),
    (["--losses", "1.2"], "--losses '1.2' must be <= 1.0"),
    (["--losses", ","], "--losses ',' gives no value"),
    (["--components", "LS,WING"], "--components: unknown component(s) WING; valid: VEL,AOA"),
    (["--mode", "bias"], "--mode 'bias': campaign detectability sets the mode per family"),
    (["--runs", "0"], "--runs '0' must be >= 1"),
    (["--failure-jitter", "-1"], "--failure-jitter '-1' must be >= 0"),
    (["--failure-time", "x"], "--failure-time 'x' is not a number"),
])
def test_cli_refuses_bad_options_by_name(argv, expected, capsys, tmp_path):
    assert main(["campaign", "detectability", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert expected in err, err
    assert "Traceback" not in err and not (tmp_path / "o").exists()


def test_cli_help_teaches(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["campaign", "detectability", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    for text in ("examples:", "--sizes", "--rates", "--losses", "sigma", "0.005 g", "Clopper-Pearson",
                 "bias.png", "--markdown", "--failure-jitter", "--failure-time"):
        assert text in out, text


@pytest.mark.slow
def test_tiny_campaign_end_to_end(tmp_path, capsys):
    out = tmp_path / "c"
    argv = ["campaign", "detectability", "--components", "AOA,LS", "--sizes", "30", "--rates", "20",
            "--losses", "1", "--runs", "1", "--workers", "1", "--out", str(out), "--quiet"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    stored = ResultsStore(out).records()
    assert len(stored) == 3 and {(r["family"], r["component"]) for r in stored} == {
        ("bias", "AOA"), ("drift", "AOA"), ("loss", "LS")}
    assert len({r["seed"] for r in stored if r["component"] == "AOA"}) == 1
    summary = json.loads((out / "summary.json").read_text())
    assert summary["command"].startswith("f16mmae campaign detectability")
    # the summary is the stored records' arithmetic
    for fam in summary["families"].values():
        for comp in fam["components"]:
            for p in comp["points"]:
                recs = [r for r in stored if r["component"] == comp["component"] and r["size"] == p["size"]]
                assert p == summarize_point(p["size"], p["value"], recs)
                assert p["detected"]["count"] == sum(r["detected"] for r in recs)
    # a 30-sigma AOA bias is seen by the bank (a loud failure, not a tuned result)
    aoa = next(r for r in stored if r["family"] == "bias")
    assert aoa["any_declared"], aoa["declarations"]
    assert all((out / f"{f}.png").stat().st_size > 1000 for f in ("bias", "drift", "loss"))
    assert "P(detect)" in text and "AOA" in text and "LS" in text
    assert "detectability" in (out / "report.html").read_text()
    md = tmp_path / "d.md"
    assert main(["report", str(out), "--markdown", str(md)]) == 0
    page = md.read_text()
    assert "f16mmae campaign detectability --components AOA,LS" in page and "| bias | AOA | 30 sigma |" in page
    # the same command again flies nothing
    assert main(argv) == 0
    assert "(0 run, 3 resumed)" in capsys.readouterr().out
