"""The maneuver campaign: the maneuvers planned at a point (hand-checked strings), a tiny real
campaign (records carry the maneuver, seeds common across points, summary rates against
counts, figures, report pages, resume), the soak flying maneuvers, and the CLI's errors."""
from __future__ import annotations

import json

import numpy as np
import pytest

from f16mmae.campaign.engine.config import CampaignError
from f16mmae.campaign.engine.store import ResultsStore
from f16mmae.campaign.envelope.points import parse_mach_alt, select_points
from f16mmae.campaign.maneuver import ManeuverCampaign, maneuver_spec, run_maneuver
from f16mmae.campaign.soak.campaign import SoakCampaign, plan as soak_plan, profile
from f16mmae.banks import load_bank
from f16mmae.cli.main import main
from f16mmae.loop.flight import fly
from f16mmae.report.markdown import summary_markdown
from f16mmae.truth import Scenario

from campaign_support import CountingExecutor


def test_maneuver_specs_at_a_point():
    assert maneuver_spec("climb", 0.4, 20_000.0, 2.0) == "climb@2:to=24000ft:rate=3000fpm"
    assert maneuver_spec("climb", 0.4, 33_000.0, 2.0) == "climb@2:to=35000ft:rate=3000fpm"
    assert maneuver_spec("descend", 0.4, 7_000.0, 2.0) == "descend@2:to=5000ft:rate=3000fpm"
    assert maneuver_spec("accel", 0.4, 20_000.0, 2.0) == "accel@2:to=0.5mach:rate=0.01mach/s"
    assert maneuver_spec("accel", 0.75, 20_000.0, 2.0) == "decel@2:to=0.65mach:rate=0.01mach/s"
    assert maneuver_spec("turn", 0.4, 20_000.0, 2.0) == "turn@2:bank=30deg"
    with pytest.raises(CampaignError, match="unknown maneuver 'loop'"):
        maneuver_spec("loop", 0.4, 20_000.0, 2.0)


def test_the_points_are_checked_as_every_campaign_with_points_checks_them():
    """engine.points.check_points: no point, a label twice, one flight condition twice (the same
    runs under two labels), a point outside the envelope; refused by name before planning."""
    nom, custom = select_points("NOM")[0], parse_mach_alt("0.4:20000,0.5:30000")
    for points, message in (((), "no flight point selected"),
                            ((nom, nom), "point label\\(s\\) used twice"),
                            ((nom, custom[0]), "points NOM and C1 are the same flight condition"),
                            ((type(nom)("X", 0.95, 20000.0, "custom"),), "point X: ")):
        with pytest.raises(CampaignError, match=message):
            ManeuverCampaign(points=points).validate()
    ManeuverCampaign(points=(nom, custom[1])).validate()


def test_tiny_maneuver_campaign(tmp_path):
    cfg = ManeuverCampaign(points=select_points("NOM") + parse_mach_alt("0.5:15000"), runs=1,
                           maneuvers=("climb", "turn"), cases=("NONE", "LS"), maneuver_time_s=1.0,
                           failure_time_s=3.0, duration_s=6.0)
    ex = CountingExecutor()
    out = run_maneuver(cfg, tmp_path, ex, show_progress=False)
    assert (out.executed, ex.submitted) == (8, 8)
    records = ResultsStore(tmp_path).records()
    for r in records:
        sc = Scenario.from_dict(r["scenario"])
        assert r["kind"] == "maneuver" and [str(m) for m in sc.maneuvers] == r["scenario"]["maneuvers"]
        assert r["scenario"]["maneuvers"][0].startswith(r["maneuver"])
    # common random numbers: a (maneuver, case, run) flies one seed at both points
    assert len({(r["maneuver"], r["case"], r["seed"]) for r in records}) == 4
    s = json.loads((tmp_path / "summary.json").read_text())
    for row in s["by_maneuver"]:
        recs = [r for r in records if r["maneuver"] == row["maneuver"]]
        fail = [r for r in recs if r["case"] != "NONE"]
        assert row["rates"]["correct"]["count"] == sum(r["outcome"] == "correct" for r in fail)
        assert row["false_alarm_runs"] == sum(r["false_alarm"] for r in recs)
        assert row["per_hour"]["events"] == sum(r["false_declarations"] for r in recs)
        assert row["per_hour"]["exposure"] == pytest.approx((2 * 6.0 + 2 * 3.0) / 3600.0)
    assert {c["maneuver_spec"] for c in s["by_point"]} == {
        "climb@1:to=24000ft:rate=3000fpm", "climb@1:to=19000ft:rate=3000fpm", "turn@1:bank=30deg"}
    for f in s["figures"].values():
        assert (tmp_path / f).stat().st_size > 1000
    assert "| climb |" in summary_markdown(s)
    assert main(["report", str(tmp_path)]) == 0 and (tmp_path / "report.html").exists()
    again = run_maneuver(cfg, tmp_path, ex, show_progress=False)
    assert (again.executed, again.resumed) == (0, 8)


def test_soak_flies_a_profile_from_the_design_point():
    ms, need = profile("tour", 0.4, 20_000.0)
    assert need == 540.0 and ms[0] == "climb@10:to=24000ft:rate=2000fpm"
    Scenario(duration_s=need, maneuvers=ms)  # a valid schedule
    high, _ = profile("tour", 0.75, 33_000.0)
    assert high[0].startswith("descend@10:to=29000ft") and high[2].startswith("decel@150:to=0.65mach")
    _, _, bank = load_bank("tuned")
    cfg = SoakCampaign(hours=0.3, duration_s=540.0, profile="tour").validate()
    specs = soak_plan(cfg, "tuned", "tuned", bank)
    assert all(s["scenario"]["maneuvers"] == list(Scenario(duration_s=540, maneuvers=ms).to_dict()["maneuvers"])
               for s in specs)
    with pytest.raises(CampaignError, match="needs flights of at least 540 s"):
        SoakCampaign(hours=0.3, duration_s=300.0, profile="tour").validate()
    plain = soak_plan(SoakCampaign(hours=0.1, duration_s=60.0).validate(), "tuned", "tuned", bank)
    assert "maneuvers" not in plain[0]["scenario"]


@pytest.mark.parametrize("argv, expected", [
    (["--maneuvers", "climb,loop"], "--maneuvers: unknown maneuver(s) LOOP"),
    (["--failure-time", "1", "--maneuver-time", "2"], "must come after --maneuver-time"),
    (["--points", "random:0"], "random:N[:seed=S]"),
])
def test_cli_errors(argv, expected, capsys, tmp_path):
    assert main(["campaign", "maneuver", *argv, "--out", str(tmp_path / "x")]) == 2
    assert expected in capsys.readouterr().err


def test_the_hold_profile_keeps_a_severe_turbulence_flight_at_its_design_condition():
    """profile hold engages the pilot's outer loop from 0 s (altitude, Mach, wings level): in
    two minutes of severe turbulence on raw feedback the trimmed aircraft alone wanders
    hundreds of feet and past 20 deg of bank; held, it stays within 100 ft and 16 deg."""
    ms, need = profile("hold", 0.4, 20_000.0)
    assert ms == ("turn@0:bank=0deg",) and need == 0.0
    _, _, bank = load_bank("tuned")
    excursions = {}
    for maneuvers in ((), ms):
        sc = Scenario(mach=0.4, alt_ft=20_000.0, turbulence="severe", duration_s=120.0, seed=3, feedback="raw",
                      maneuvers=maneuvers)
        log = fly(sc, bank, record_series=True, record_probabilities=False).series["truth_log"]
        state, names = log["state"], log["state_names"]
        excursions[maneuvers] = (np.abs(state[:, names.index("alt_ft")] - 20_000.0).max(),
                                 np.degrees(np.abs(state[:, names.index("phi_rad")]).max()))
    alone, held = excursions[()], excursions[ms]
    assert alone[0] > 300.0 and alone[1] > 20.0, alone
    assert held[0] < 100.0 and held[1] < 16.0, held
    specs = soak_plan(SoakCampaign(hours=0.1, duration_s=60.0, profile="hold").validate(), "tuned", "tuned", bank)
    assert all(s["scenario"]["maneuvers"] == ["turn@0:bank=0deg"] for s in specs)


def test_the_failure_jitter_moves_each_maneuver_runs_failure_and_end():
    """``--failure-jitter J`` (engine.failure_runs): the failure and the end of run n shift by the
    seeded J x, the maneuver stays where it began."""
    from f16mmae.campaign.engine.failure_runs import failure_offset
    from f16mmae.campaign.maneuver.campaign import plan
    from f16mmae.cli import campaign_maneuver
    from f16mmae.cli.main import build_parser
    args = build_parser().parse_args(["campaign", "maneuver", "--maneuvers", "turn", "--cases", "LS",
                                      "--runs", "3", "--failure-jitter", "1"])
    cfg = campaign_maneuver.config_from_args(args)
    assert cfg.failure_jitter_s == 1.0
    bank = load_bank("tuned")[2]
    plain = plan(ManeuverCampaign(**{**cfg.__dict__, "failure_jitter_s": 0.0}), "tuned", "tuned", bank)
    for a, b in zip(plain, plan(cfg, "tuned", "tuned", bank)):
        offset = failure_offset(b["seed"], 1.0)
        assert b["scenario"]["failures"][0]["time_s"] == pytest.approx(6.0 + offset)
        assert b["scenario"]["duration_s"] == pytest.approx(14.0 + offset)
        assert b["scenario"]["maneuvers"] == a["scenario"]["maneuvers"]
    with pytest.raises(CampaignError, match="--failure-jitter 61 must lie in"):
        ManeuverCampaign(**{**cfg.__dict__, "failure_jitter_s": 61.0}).validate()
