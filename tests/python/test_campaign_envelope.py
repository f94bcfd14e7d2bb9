"""The off-nominal (flight-envelope) campaign: q̄, the paper's Fig. 9 grid, point selection,
the acceptability rule, a tiny real campaign (records, summary, figures, resume, the design
bank unchanged at every point) and the CLI's errors."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from f16mmae.banks import load_bank
from f16mmae.campaign.engine import failure_runs
from f16mmae.campaign.single import SingleCampaign
from f16mmae.campaign.envelope import EnvelopeCampaign, acceptable, point_metrics, run_envelope
from f16mmae.campaign.envelope.points import (NOMINAL, PAPER_POINTS, QLINE_LABELS, EnvelopeError,
                                              EnvelopePoint, check_distinct, dynamic_pressure_psf,
                                              parse_mach_alt, pressure_psf, select_points)
from f16mmae.campaign.engine.scoring import score_run
from f16mmae.campaign.engine.store import ResultsStore
from f16mmae.cli.main import main

from campaign_support import CountingExecutor

PA_TO_PSF = 1.0 / 47.880258889


# -- q̄ ---------------------------------------------------------------------------------------
def test_pressure_and_dynamic_pressure_against_standard_values():
    # US Standard Atmosphere 1976: sea level 101,325 Pa; 11 km geopotential (tropopause) 22,632.06 Pa
    assert pressure_psf(0.0) == pytest.approx(101_325.0 * PA_TO_PSF, rel=1e-9)
    h_tropo_ft = 11_000.0 * 6_356_766.0 / (6_356_766.0 - 11_000.0) / 0.3048  # geometric
    assert pressure_psf(h_tropo_ft) == pytest.approx(22_632.06 * PA_TO_PSF, rel=2e-5)
    # q̄ = rho V^2 / 2 at sea level, Mach 1: rho0 = 1.225 kg/m^3, a0 = 340.294 m/s
    assert dynamic_pressure_psf(1.0, 0.0) == pytest.approx(0.5 * 1.225 * 340.294**2 * PA_TO_PSF, rel=1e-4)
    with pytest.raises(EnvelopeError, match="troposphere"):
        pressure_psf(40_000.0)


@pytest.mark.parametrize("mach, alt_ft", [(0.4, 20_000.0), (0.35, 20_000.0), (0.4, 25_000.0), (0.4, 15_000.0)])
def test_dynamic_pressure_agrees_with_jsbsim_at_trim(mach, alt_ft):
    from f16mmae.truth.aircraft import trimmed_fdm

    fdm, _ = trimmed_fdm(mach, alt_ft)
    assert pressure_psf(alt_ft) == pytest.approx(fdm["atmosphere/P-psf"], rel=5e-4)
    assert dynamic_pressure_psf(mach, alt_ft) == pytest.approx(fdm["aero/qbar-psf"], rel=2e-3)


# -- the grid ---------------------------------------------------------------------------------
def test_paper_grid_is_fig9_as_documented():
    labels = [p.label for p in PAPER_POINTS]
    assert labels == ["NOM"] + [str(n) for n in range(1, 25)]
    assert (NOMINAL.mach, NOMINAL.alt_ft) == (0.4, 20_000.0)
    local = [p for p in PAPER_POINTS if p.group == "local"]
    assert len(local) == 20
    for p in local:  # a checkerboard of 0.005 Mach x 500 ft steps around NOM
        i, j = (p.mach - 0.4) / 0.005, (p.alt_ft - 20_000.0) / 500.0
        assert abs(i - round(i)) < 1e-9 and abs(j - round(j)) < 1e-9, p
        assert (round(i) + round(j)) % 2 == 0, p
    m = [p.mach for p in local] + [0.4]
    h = [p.alt_ft for p in local] + [20_000.0]
    assert max(m) - min(m) == pytest.approx(0.03) and max(h) - min(h) == 3000.0  # the paper's region
    ext = {p.label: p for p in PAPER_POINTS if p.group == "extrema"}
    assert sorted(ext) == ["21", "22", "23", "24"]
    # the extrema are symmetric about NOM: 21/23 in altitude, 22/24 in Mach
    assert ext["21"].mach == ext["23"].mach == 0.4
    assert ext["21"].alt_ft - 20_000 == 20_000 - ext["23"].alt_ft == 5000
    assert ext["22"].alt_ft == ext["24"].alt_ft == 20_000
    assert ext["24"].mach - 0.4 == pytest.approx(0.4 - ext["22"].mach) == pytest.approx(0.05)
    check_distinct(PAPER_POINTS)
    # the paper's constant-q̄ axis: within 1 % of NOM's q̄; the altitude extrema are not
    q_nom = NOMINAL.qbar_psf
    for p in select_points("qline"):
        assert abs(p.qbar_psf / q_nom - 1) < 0.01, p
    assert ext["21"].qbar_psf < 0.85 * q_nom < 1.15 * q_nom < ext["23"].qbar_psf


def test_truth_model_trims_at_every_default_point():
    from f16mmae.truth import actuators
    from f16mmae.truth.aircraft import trimmed_fdm

    lim = np.asarray(actuators.POSITION_LIMIT_RAD)
    for p in PAPER_POINTS:
        fdm, tp = trimmed_fdm(p.mach, p.alt_ft)
        assert fdm["position/h-sl-ft"] == pytest.approx(p.alt_ft, abs=1.0)
        assert fdm["velocities/mach"] == pytest.approx(p.mach, abs=1e-4)
        assert np.all(np.abs(tp.u_rad) < 0.5 * lim), p


# -- selections ---------------------------------------------------------------------------------
def test_point_selection():
    assert select_points("all") == PAPER_POINTS
    assert [p.label for p in select_points("LOCAL")] == ["NOM"] + [str(n) for n in range(1, 21)]
    assert [p.label for p in select_points("extrema")] == ["NOM", "21", "22", "23", "24"]
    assert sorted(p.label for p in select_points("qline")) == sorted(QLINE_LABELS)
    assert [p.label for p in select_points(" 3, nom,1 ")] == ["NOM", "1", "3"]
    for bad, msg in (("25", "unknown point(s) 25"), ("0", "unknown point(s) 0"), ("", "unknown point(s) ''"),
                     ("1,1", "lists a point twice"), ("everything", "valid: all | local | extrema | qline")):
        with pytest.raises(EnvelopeError, match=msg.replace("(", r"\(").replace(")", r"\)").replace("|", r"\|")):
            select_points(bad)


def test_custom_points_and_duplicates():
    pts = parse_mach_alt("0.42:21000, 0.38:19000")
    assert [(p.label, p.mach, p.alt_ft, p.group) for p in pts] == [
        ("C1", 0.42, 21000.0, "custom"), ("C2", 0.38, 19000.0, "custom")]
    for bad, msg in (("0.42", "is not MACH:ALT_FT"), ("a:b", "is not MACH:ALT_FT"),
                     ("0.9:20000", "outside the supported range 0.3-0.8"), (",", "holds no point")):
        with pytest.raises(EnvelopeError, match=msg):
            parse_mach_alt(bad)
    with pytest.raises(EnvelopeError, match="points NOM and C1 are the same flight condition"):
        check_distinct((NOMINAL, EnvelopePoint("C1", 0.4, 20000.0, "custom")))
    with pytest.raises(EnvelopeError, match="no flight point selected"):
        check_distinct(())


# -- acceptability ------------------------------------------------------------------------------
def _rec(case, decls, t_f=3.0):
    return {"case": case, **score_run(case, None if case == "NONE" else t_f,
                                      [{"hypothesis": h, "time_s": t} for h, t in decls])}


def test_point_metrics_and_acceptability_rule():
    good = [_rec("LS", [("LS", 3.5)]) for _ in range(9)] + [_rec("PIT", [])]  # 9/10, one missed
    m = point_metrics(good + [_rec("NONE", [])])
    assert (m["failure_runs"], m["correct"], m["missed"], m["false_alarm_runs"]) == (10, 9, 1, 0)
    assert m["correct_fraction"] == pytest.approx(0.9) and m["latency_median_s"] == pytest.approx(0.5)
    assert acceptable(m)  # 90 % is enough
    assert not acceptable(m, correct_fraction_min=0.95)
    eight = point_metrics(good[:8] + [_rec("PIT", []), _rec("AZ", [("YAW", 4.0)])])
    assert eight["wrong"] == 1 and not acceptable(eight)  # 8/10
    # a false alarm anywhere -- here a NONE run that declares and backs out -- is not acceptable
    fa = point_metrics(good[:9] + [_rec("NONE", [("AZ", 1.0), ("NONE", 2.0)])])
    assert fa["correct_fraction"] == 1.0 and fa["none_correct"] == 1 and fa["false_alarm_runs"] == 1
    assert not acceptable(fa) and acceptable(fa, false_alarms_max=1)
    early = point_metrics([_rec("LS", [("AOA", 1.0), ("LS", 3.2)])])  # correct, but alarmed early
    assert early["correct"] == 1 and early["false_alarm_runs"] == 1 and not acceptable(early)
    only_none = point_metrics([_rec("NONE", [])])
    assert only_none["correct_fraction"] is None and only_none["latency_median_s"] is None
    assert acceptable(only_none)
    assert not acceptable(point_metrics([]))


# -- a tiny real campaign -------------------------------------------------------------------------


@pytest.mark.slow
def test_tiny_envelope_campaign_records_summary_figures_and_resume(tmp_path):
    cfg = EnvelopeCampaign(points=select_points("NOM,22"), runs=1, cases=("NONE", "PIT"),
                           failure_time_s=2.0, duration_s=4.5)
    ex = CountingExecutor()
    first = run_envelope(cfg, tmp_path, ex, show_progress=False)
    assert (first.executed, first.resumed, ex.submitted) == (4, 0, 4)
    records = ResultsStore(tmp_path).records()
    assert len(records) == 4
    _, _, bank = load_bank("tuned")
    where = {"NOM": (0.4, 20000.0), "22": (0.35, 20000.0)}
    for r in records:
        assert (r["scenario"]["mach"], r["scenario"]["alt_ft"]) == where[r["point"]]
        assert r["bank_hash"] == bank.content_hash  # the design bank, not re-designed per point
        assert r["seed"] == r["scenario"]["seed"] >= 1 and r["version"]
    # common random numbers: run 0 of a case flies the same seed at both points
    assert len({(r["case"], r["seed"]) for r in records}) == 2
    # the NOM point plans exactly the runs of the single campaign at the design point
    banks = {"tuned": ("tuned", bank)}
    nominal = SingleCampaign(runs=1, cases=("NONE", "PIT"), baseline=None, failure_time_s=2.0, duration_s=4.5)
    assert {s["run_key"] for s in failure_runs.plan(nominal, banks)} == {r["run_key"] for r in records if r["point"] == "NOM"}

    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["kind"] == "envelope" and summary["bank_hash"] == bank.content_hash
    assert [p["label"] for p in summary["points"]] == ["NOM", "22"]
    for p in summary["points"]:
        mine = point_metrics([r for r in records if r["point"] == p["label"]])
        assert {k: p[k] for k in mine} == mine
        assert p["acceptable"] == acceptable(mine)
        assert [c["case"] for c in p["cases"]] == ["NONE", "PIT"] and sum(c["runs"] for c in p["cases"]) == 2
    nom, p22 = summary["points"]
    assert nom["trim_offset"] == {"stab_deg": 0.0, "vel_fps": 0.0, "aoa_deg": 0.0, "az_g": 0.0}
    assert p22["trim_offset"]["vel_fps"] < -40 and p22["trim_offset"]["aoa_deg"] > 1  # slower, higher alpha
    assert p22["qbar_psf"] == pytest.approx(dynamic_pressure_psf(0.35, 20000.0), abs=1e-3)
    for name in summary["figures"].values():
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert set(summary["figures"]) == {"map", "cases"}

    ex = CountingExecutor()
    again = run_envelope(cfg, tmp_path, ex, show_progress=False)
    assert (again.executed, again.resumed, ex.submitted) == (0, 4, 0)
    assert len(ResultsStore(tmp_path).records()) == 4
    assert json.loads((tmp_path / "summary.json").read_text())["points"] == summary["points"]


# -- CLI ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("argv, expected", [
    (["--points", "25"], "--points: unknown point(s) 25; valid: all | local | extrema | qline"),
    (["--points", "1,1"], "lists a point twice"),
    (["--mach-alt", "0.9:20000"], "mach 0.9 outside the supported range 0.3-0.8"),
    (["--mach-alt", "0.42"], "'0.42' is not MACH:ALT_FT"),
    (["--points", "NOM", "--mach-alt", "0.4:20000"], "points NOM and C1 are the same flight condition"),
    (["--cases", "LS,XX"], "unknown case(s) XX; valid: NONE,LS,RS"),
    (["--runs", "0"], "--runs '0' must be >= 1"),
    (["--mode", "null"], "unknown failure mode 'null' for actuator LS; valid: complete, stuck, hardover, loss"),
    (["--seed", "x"], "--seed 'x' is not an integer"),
    (["--turbulence", "gusty"], "'gusty' is unknown; valid: none, light, moderate, severe"),
    (["--tuning", "wobbly"], "--tuning 'wobbly' is neither tuned, untuned"),
    (["--threshold", "0.3"], "--threshold 0.3 must lie in (0.5, 1)"),
    (["--workers", "2", "--scheduler", "tcp://h:1"], "not both"),
])
def test_cli_errors_name_the_bad_value(argv, expected, capsys):
    assert main(["campaign", "envelope", *argv]) == 2
    err = capsys.readouterr().err
    assert expected in err, err
    assert "Traceback" not in err


def test_cli_help_teaches(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["campaign", "envelope", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    for text in ("examples:", "ACCEPTABLE", "q̄", "qline", "envelope_map.png", "envelope_cases.png"):
        assert text in out, text
    import re

    rows = re.findall(r"^\s+(\w+) (nominal|local|extrema)\s+(0\.\d{3})\s+(\d+)\s+([\d.]+)$", out, re.M)
    assert [r[0] for r in rows] == [p.label for p in PAPER_POINTS]
    assert all(float(r[2]) == p.mach and float(r[3]) == p.alt_ft for r, p in zip(rows, PAPER_POINTS))


@pytest.mark.slow
def test_cli_runs_one_point_and_prints_the_table(tmp_path, capsys):
    argv = ["campaign", "envelope", "--points", "NOM", "--cases", "NONE", "--runs", "1",
            "--workers", "1", "--out", str(tmp_path), "--quiet"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.strip().startswith("NOM"))
    # correct (no failure case), false-alarm runs, transient-wrong runs, latency, acceptable, verdict
    assert row.split() == ["NOM", "0.400", "20000", "109.0", "-", "0", "0", "-", "yes", "consistent"]
    assert "envelope_map.png" in out and "(1 run, 0 resumed)" in out
    page = (tmp_path / "report.html").read_text()
    assert "data:image/png;base64," in page and "<td>NOM</td><td>0.400</td><td>20000</td>" in page
    (tmp_path / "report.html").unlink()
    assert main(["report", str(tmp_path)]) == 0  # `f16mmae report` knows the kind
    assert (tmp_path / "report.html").read_text() == page


# -- random points -----------------------------------------------------------------------------
def test_random_points_are_a_seeded_latin_hypercube():
    from f16mmae.campaign.envelope.points import random_points
    pts = random_points(8, seed=5, trims=lambda m, h: True)
    assert [p.label for p in pts] == [f"R{i}" for i in range(1, 9)] and {p.group for p in pts} == {"random"}
    # one point in each of the 8 Mach strata and each of the 8 altitude strata
    assert sorted(math.floor((p.mach - 0.3) / 0.5 * 8) for p in pts) == list(range(8))
    assert sorted(math.floor((p.alt_ft - 5000.0) / 30000.0 * 8) for p in pts) == list(range(8))
    assert random_points(8, seed=5, trims=lambda m, h: True) == pts
    assert random_points(8, seed=6, trims=lambda m, h: True) != pts
    assert select_points("random:3:seed=2") == random_points(3, 2)  # the real trim: these trim


def test_random_points_redraw_inside_their_cell_or_name_it():
    from f16mmae.campaign.envelope.points import random_points
    refused = []

    def trims(mach, alt_ft):  # refuses about half of every cell: altitudes of an odd number of ft
        ok = round(alt_ft) % 2 == 0
        refused.extend([] if ok else [(mach, alt_ft)])
        return ok

    pts = random_points(40, seed=1, trims=trims)
    assert refused  # some draws were refused and redrawn
    assert all(trims(p.mach, p.alt_ft) for p in pts)
    assert sorted(math.floor((p.mach - 0.3) / 0.5 * 40) for p in pts) == list(range(40))
    with pytest.raises(EnvelopeError, match=r"random point 1 of 2 \(seed 1\): no trim in 20 draws inside its cell Mach 0.300-0.550"):
        random_points(2, 1, trims=lambda m, h: False)


@pytest.mark.parametrize("text", ["random", "random:0", "random:x", "random:5:sed=3", "random:5:seed=0"])
def test_random_selection_errors_name_the_form(text):
    with pytest.raises(EnvelopeError, match=r"random:N\[:seed=S\]"):
        select_points(text)


def test_compare_draws_two_campaigns_side_by_side(tmp_path, capsys):
    cfg = EnvelopeCampaign(points=select_points("NOM") + parse_mach_alt("0.6:34000"), runs=1,
                           cases=("NONE", "PIT"), failure_time_s=2.0, duration_s=4.0)
    for name in ("a", "b"):
        run_envelope(cfg, tmp_path / name, CountingExecutor(), show_progress=False)
    out = tmp_path / "cmp"
    assert main(["campaign", "envelope", "--compare", f"{tmp_path / 'a'},{tmp_path / 'b'}", "--out", str(out)]) == 0
    assert (out / "envelope_compare.png").stat().st_size > 10_000
    (tmp_path / "c").mkdir()
    (tmp_path / "c" / "summary.json").write_text(json.dumps({"kind": "soak"}))
    assert main(["campaign", "envelope", "--compare", f"{tmp_path / 'a'},{tmp_path / 'c'}", "--out", str(out)]) == 2
    assert "is of kind 'soak', not 'envelope'" in capsys.readouterr().err
    assert main(["campaign", "envelope", "--compare", str(tmp_path / "a"), "--out", str(out)]) == 2
    assert "give two or more campaign directories" in capsys.readouterr().err


def test_compared_panels_name_the_settings_in_which_they_differ():
    """Two campaigns of one bank are told apart by the estimator settings that differ between
    them (``figures.settings_differences``), in name order, wrapped, ``-`` where one lacks it, long values cut and the lines capped."""
    from f16mmae.campaign.envelope.figures import settings_differences
    a = {"estimator_settings": {"adapt_turbulence": True, "dwell_s_per_hypothesis": "VEL=1,AZ=0.5"}}
    b = {"estimator_settings": {"adapt_turbulence": True, "dwell_s_per_hypothesis": "VEL=1,AZ=0.5,AOA=0.75",
                                "complete_trim_time_constant_s": 10.0}}
    assert settings_differences([a, b]) == [
        "complete_trim_time_constant_s=-, dwell_s_per_hypothesis=VEL=1,AZ=0.5",
        "complete_trim_time_constant_s=10.0, dwell_s_per_hypothesis=VEL=1,AZ=0.5,AOA=0.75"]
    assert settings_differences([a, b], width=48)[1] == \
        "complete_trim_time_constant_s=10.0\ndwell_s_per_hypothesis=VEL=1,AZ=0.5,AOA=0.75"
    assert settings_differences([a, b], width=40)[1] == \
        "complete_trim_time_constant_s=10.0\ndwell_s_per_hypothesis=VEL=1,AZ=0.5,A..."
    many = {"estimator_settings": {f"s{i}": i for i in range(9)}}
    assert settings_differences([many, {}], width=24, max_lines=2) == [
        "s0=0, s1=1, s2=2, s3=3\n... and 5 more settings",
        "s0=-, s1=-, s2=-, s3=-\n... and 5 more settings"]
    assert settings_differences([a, a]) == ["", ""]
    assert settings_differences([{"estimator": {"p_min": 1e-9}}, {}]) == ["p_min=1e-09", "p_min=-"]


def test_the_envelope_takes_the_failure_instant_of_the_single_campaign():
    """``--failure-time`` and ``--failure-jitter`` (cli.campaign_common.add_failure_instant): the
    envelope's runs fail and end as the single campaign's, at every point."""
    from f16mmae.cli import campaign_envelope
    from f16mmae.cli.main import build_parser
    args = build_parser().parse_args(["campaign", "envelope", "--points", "NOM,1", "--cases", "RUD",
                                      "--failure-time", "20", "--failure-jitter", "1"])
    cfg = campaign_envelope.config_from_args(args)
    assert (cfg.failure_time_s, cfg.failure_jitter_s, cfg.duration_s) == (20.0, 1.0, 25.0)
    bank = load_bank("tuned")[2]
    for p in cfg.points:
        for spec in failure_runs.plan(cfg, {"tuned": ("tuned", bank)}, p.mach, p.alt_ft):
            offset = failure_runs.failure_offset(spec["seed"], 1.0)
            assert spec["scenario"]["failures"][0]["time_s"] == pytest.approx(20.0 + offset)
            assert spec["scenario"]["duration_s"] == pytest.approx(25.0 + offset)
    with pytest.raises(failure_runs.CampaignError, match="--failure-jitter -1 must lie in"):
        EnvelopeCampaign(failure_jitter_s=-1.0).validate()
