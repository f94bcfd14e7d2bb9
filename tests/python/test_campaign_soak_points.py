"""The soak over several flight points: the plan (common seeds across points and levels, a key
per flight, each spec naming its point), a soak without points planning the specs and keys it
always had, the per-point summary against hand-made declarations (pooled and per point, the
drilldown and the flights that left their condition naming their point, labels taken from the
soak flying them), the CLI's refusals before any flight, and a short real soak over two points
(map, page, Markdown)."""
from __future__ import annotations

import io
import json
from types import SimpleNamespace

import numpy as np
import pytest

from f16mmae import __version__
from f16mmae.banks import load_bank
from f16mmae.campaign.engine import intervals
from f16mmae.campaign.engine.config import CampaignError
from f16mmae.campaign.engine.seeds import evaluation_seed
from f16mmae.campaign.engine.store import RECORDS_FILE, ResultsStore, run_key
from f16mmae.campaign.envelope.points import parse_mach_alt, select_points
from f16mmae.campaign.soak import SoakCampaign, run_soak
from f16mmae.campaign.soak import campaign as soak_campaign
from f16mmae.campaign.soak.campaign import plan, profile
from f16mmae.campaign.soak.report import soak_markdown, soak_page
from f16mmae.cli.campaign_soak import print_summary
from f16mmae.cli.main import main
from f16mmae.truth import Scenario

from campaign_support import CountingExecutor

#: The fields of a soak spec before there were points.
SPEC_FIELDS = {"run_key", "level", "run_index", "seed", "tuning", "bank", "bank_hash", "version", "scenario",
               "estimator"}


@pytest.fixture(scope="module")
def tuned():
    return load_bank("tuned")[2]


# -- the plan ------------------------------------------------------------------------------------
def test_a_plan_over_two_points_and_two_levels(tuned):
    points = parse_mach_alt("0.35:15000,0.6:25000")
    cfg = SoakCampaign(hours=120 / 3600, duration_s=60.0, turbulence="light,moderate", seed=5,
                       points=points).validate()
    specs = plan(cfg, "tuned", "tuned", tuned)
    assert cfg.flights == 2 and len(specs) == 2 * 2 * 2
    # point by point, level by level, flight by flight
    assert [(s["point"], s["level"], s["run_index"]) for s in specs] == [
        (p, lvl, n) for p in ("C1", "C2") for lvl in ("light", "moderate") for n in (0, 1)]
    for s in specs:
        point = points[int(s["point"][1]) - 1]
        assert (s["scenario"]["mach"], s["scenario"]["alt_ft"]) == (point.mach, point.alt_ft)
        assert s["scenario"]["turbulence"] == s["level"] and s["scenario"]["failures"] == []
        # common random numbers: flight n's seed at every point and level
        assert s["seed"] == s["scenario"]["seed"] == evaluation_seed("soak", 5, s["run_index"])
        assert set(s) == SPEC_FIELDS | {"point"}
        assert s["run_key"] == run_key({"kind": "soak", "scenario": s["scenario"], "estimator": cfg.estimator_options(),
                                        "bank_hash": tuned.content_hash, "version": __version__})
    assert len({s["seed"] for s in specs}) == 2
    assert len({s["run_key"] for s in specs}) == len(specs)


def test_a_soak_without_points_plans_the_specs_and_keys_it_always_had(tuned):
    """The specs of a soak at --mach/--alt-ft and at the design point, built here field by field
    as the plan built them before there were points: no ``point``, the same run keys."""
    cases = [(SoakCampaign(hours=120 / 3600, duration_s=60.0, turbulence="light,severe", seed=2, mach=0.5,
                           alt_ft=15000.0), (0.5, 15000.0)),
             (SoakCampaign(hours=120 / 3600, duration_s=60.0, turbulence="none,moderate", seed=3),
              (float(tuned.mach), float(tuned.alt_ft)))]
    for cfg, (mach, alt_ft) in cases:
        specs = plan(cfg.validate(), "tuned", "tuned", tuned)
        expected = []
        for level in cfg.levels():
            for n in range(2):
                seed = evaluation_seed("soak", cfg.seed, n)
                scenario = Scenario(mach=mach, alt_ft=alt_ft, turbulence=level, dither=cfg.dither_spec(),
                                    duration_s=60.0, seed=seed, feedback=cfg.feedback).to_dict()
                key = run_key({"kind": "soak", "scenario": scenario, "estimator": cfg.estimator_options(),
                               "bank_hash": tuned.content_hash, "version": __version__})
                expected.append({"run_key": key, "level": level, "run_index": n, "seed": seed, "tuning": "tuned",
                                 "bank": "tuned", "bank_hash": tuned.content_hash, "version": __version__,
                                 "scenario": scenario, "estimator": cfg.estimator_options()})
        assert specs == expected


def test_each_point_flies_its_own_profile_and_a_maneuver_that_does_not_fit_is_refused_naming_the_point(tuned):
    points = parse_mach_alt("0.4:20000,0.75:33000")
    cfg = SoakCampaign(hours=540 / 3600, duration_s=540.0, profile="tour", points=points).validate()
    specs = plan(cfg, "tuned", "tuned", tuned)
    by_point = {s["point"]: s["scenario"]["maneuvers"] for s in specs}
    for p in points:
        assert by_point[p.label] == list(Scenario(mach=p.mach, alt_ft=p.alt_ft, duration_s=540.0,
                                                  maneuvers=profile("tour", p.mach, p.alt_ft)[0]).to_dict()["maneuvers"])
    assert by_point["C1"][0].startswith("climb@10:to=24000ft") and by_point["C2"][0].startswith("descend@10:to=29000ft")
    with pytest.raises(CampaignError, match="point C2 .*climb@10:to=23000ft"):
        SoakCampaign(hours=0.1, duration_s=60.0, maneuvers=("climb@10:to=23000ft:rate=2000fpm",),
                     points=parse_mach_alt("0.4:20000,0.5:25000")).validate()


def test_the_config_refuses_mach_with_points_and_points_twice():
    points = parse_mach_alt("0.35:15000,0.6:25000")
    with pytest.raises(CampaignError, match="--mach/--alt-ft .* or --points/--mach-alt .* not both"):
        SoakCampaign(mach=0.5, alt_ft=15000.0, points=points).validate()
    with pytest.raises(CampaignError, match="points C1 and C3 are the same flight condition"):
        SoakCampaign(points=parse_mach_alt("0.35:15000,0.6:25000,0.35:15000")).validate()
    with pytest.raises(CampaignError, match="used twice"):
        SoakCampaign(points=(points[0], soak_campaign.SoakPoint("C1", 0.5, 10000.0))).validate()


# -- the summary of hand-made flights ----------------------------------------------------------------
#: Per (Mach, turbulence): the declarations of the flight and where it leaves its condition.
_FLIGHTS = {
    (0.35, "light"): ([("LS", 100.0), ("NONE", 110.0), ("AZ", 2000.0), ("NONE", 2010.0)], None),
    (0.6, "light"): ([], None),
    (0.35, "moderate"): ([], None),
    (0.6, "moderate"): ([("RF", 1900.0)], 1800.0),
}


def _fake_fly(scenario, bank, estimator_options=None, record_probabilities=True):
    """One hour of flight whose declarations and track are :data:`_FLIGHTS`'."""
    decl, left = _FLIGHTS[(scenario.mach, scenario.turbulence)]
    track = [[0.0, scenario.mach, scenario.alt_ft], [3600.0, scenario.mach, scenario.alt_ft]]
    if left is not None:
        track.insert(1, [left, np.nan, np.nan])
    return SimpleNamespace(declarations=[{"hypothesis": h, "time_s": t} for h, t in decl], track=np.array(track),
                           estimator_settings={}, timing={"wall_s": 0.0})


def test_per_point_rates_of_hand_made_flights(tmp_path, monkeypatch):
    """Point C1 declares twice in its hour of light air, C2 never: pooled 2 in 2 h = 1/h, per point
    2/h and 0/h; in moderate air C2 leaves its condition at 1,800 s (half an hour counted, its
    later declaration apart)."""
    monkeypatch.setattr(soak_campaign, "fly", _fake_fly)
    out = tmp_path / "soak"
    cfg = SoakCampaign(hours=1.0, duration_s=3600.0, turbulence="light,moderate",
                       points=parse_mach_alt("0.35:15000,0.6:25000"))
    done = run_soak(cfg, out, CountingExecutor(), show_progress=False)
    assert len(done.records) == 4 and all("point" in r for r in done.records)
    s = json.loads((out / "summary.json").read_text())
    assert s["mach"] is None and s["alt_ft"] is None
    light, moderate = s["levels"]
    assert (light["per_hour"]["events"], light["hours"], light["per_hour"]["rate"]) == (2, 2.0, 1.0)
    assert (moderate["per_hour"]["events"], moderate["hours"]) == (0, 1.5)
    assert [p["label"] for p in s["points"]] == ["C1", "C2"]
    c1, c2 = ({q["level"]: q for q in p["levels"]} for p in s["points"])
    assert (s["points"][0]["mach"], s["points"][0]["alt_ft"]) == (0.35, 15000.0)
    assert (c1["light"]["per_hour"]["rate"], c1["light"]["hours"]) == (2.0, 1.0)
    assert c1["light"]["per_hour"]["ci95"] == intervals.poisson_rate(2, 1.0)["ci95"]
    assert c1["light"]["per_hour"]["verdict"] == "not met" and c1["light"]["hypotheses"] == {"AZ": 1, "LS": 1}
    assert (c2["light"]["per_hour"]["rate"], c2["light"]["per_hour"]["verdict"]) == (0.0, "consistent")
    assert (c2["moderate"]["hours"], c2["moderate"]["flights_left_condition"],
            c2["moderate"]["declarations_after_leaving"]) == (0.5, 1, 1)
    assert c1["moderate"]["hours"] == 1.0 and c1["moderate"]["per_hour"]["events"] == 0
    # the drilldown and the flights off their condition name their point; each command flies it there
    (bad,) = s["not_clean"]
    assert (bad["point"], bad["level"], bad["false_declarations"]) == ("C1", "light", 2)
    assert "--mach 0.35 --alt-ft 15000.0" in bad["command"] and "--turbulence light" in bad["command"]
    (left,) = s["left_condition"]
    assert (left["point"], left["level"], left["left_condition_s"]) == ("C2", "moderate", 1800.0)
    assert "--mach 0.6 --alt-ft 25000.0" in left["command"]
    assert s["figures"]["map"] == "soak_map.png" and (out / "soak_map.png").stat().st_size > 1000
    page, text = soak_page(out, s), soak_markdown(s)
    assert "<h2>Per point</h2>" in page and "The points coloured by their false declarations per flight hour" in page
    assert "at 2 points (C1, C2)" in text and "| C1 | 0.350 | 15000 | 2.00 [" in text
    assert "point C1, light flight" in text and "point C2, moderate flight 0" in text
    lines = io.StringIO()
    print_summary(s, lines)
    assert "by point: 1 of 2 without a false declaration" in lines.getvalue()
    assert "C1 (Mach 0.350, 15000 ft): light 2 (AZ 1, LS 1)" in lines.getvalue()

    # the same flights under other labels: resumed, and counted under the labels of this soak
    swapped = SoakCampaign(hours=1.0, duration_s=3600.0, turbulence="light,moderate",
                           points=parse_mach_alt("0.6:25000,0.35:15000"))
    ex = CountingExecutor()
    run_soak(swapped, out, ex, show_progress=False)
    again = json.loads((out / "summary.json").read_text())
    assert ex.submitted == 0
    assert [(p["label"], p["mach"], p["levels"][0]["per_hour"]["events"]) for p in again["points"]] == [
        ("C1", 0.6, 0), ("C2", 0.35, 2)]
    assert again["not_clean"][0]["point"] == "C2"


def test_a_single_point_summary_has_one_point_and_no_map(tmp_path, monkeypatch):
    monkeypatch.setattr(soak_campaign, "fly", _fake_fly)
    cfg = SoakCampaign(hours=1.0, duration_s=3600.0, turbulence="light", mach=0.35, alt_ft=15000.0)
    done = run_soak(cfg, tmp_path, CountingExecutor(), show_progress=False)
    s = json.loads((tmp_path / "summary.json").read_text())
    assert "point" not in done.records[0] and "point" not in s["not_clean"][0]
    assert (s["mach"], s["alt_ft"]) == (0.35, 15000.0)
    assert [(p["label"], p["mach"], p["alt_ft"]) for p in s["points"]] == [("C1", 0.35, 15000.0)]
    assert s["points"][0]["levels"][0]["per_hour"] == s["levels"][0]["per_hour"]
    assert "map" not in s["figures"] and "Per point" not in soak_page(tmp_path, s)
    assert "from Mach 0.35, 15000 ft" in soak_markdown(s)


# -- the command line ------------------------------------------------------------------------------
@pytest.mark.parametrize("args, message", [
    (["--points", "NOM,99"], "--points: unknown point(s) 99"),
    (["--points", "1,1"], "lists a point twice"),
    (["--points", "random:0"], "random:N[:seed=S]"),
    (["--mach-alt", "0.4:20000,0.4:20000"], "points C1 and C2 are the same flight condition"),
    (["--points", "NOM", "--mach-alt", "0.4:20000"], "points NOM and C1 are the same flight condition"),
    (["--mach-alt", "0.9:20000"], "--mach-alt item '0.9:20000'"),
    (["--mach-alt", "0.4"], "is not MACH:ALT_FT"),
    (["--mach", "0.5", "--alt-ft", "15000", "--points", "NOM"],
     "give --mach/--alt-ft (one flight condition) or --points/--mach-alt (flight points), not both"),
    (["--mach", "0.5", "--mach-alt", "0.6:20000"], "not both"),
    (["--points", "21", "--maneuver", "climb@10:to=23000ft"], "point 21 (Mach 0.4, 25000 ft): maneuvers"),
])
def test_cli_soak_points_bad_input(tmp_path, capsys, args, message):
    out = tmp_path / "bad"
    assert main(["campaign", "soak", "--workers", "1", "--out", str(out), *args]) == 2
    assert message in capsys.readouterr().err
    assert not (out / RECORDS_FILE).exists()


def test_cli_soak_over_two_points_end_to_end(tmp_path, capsys):
    out = tmp_path / "pts"
    argv = ["campaign", "soak", "--hours", "0.01", "--flight-s", "18", "--mach-alt", "0.45:18000",
            "--points", "NOM", "--turbulence", "light", "--workers", "1", "--quiet", "--out", str(out)]
    assert main(argv) in (0, 1)
    printed = capsys.readouterr().out
    assert "2 points (NOM, C1)" in printed and "by point:" in printed
    records = ResultsStore(out).records()
    assert len(records) == 4 and {r["point"] for r in records} == {"NOM", "C1"}
    seeds = {(r["point"], r["run_index"]): r["seed"] for r in records}
    assert seeds[("NOM", 0)] == seeds[("C1", 0)] and seeds[("NOM", 1)] == seeds[("C1", 1)]
    assert {(r["scenario"]["mach"], r["scenario"]["alt_ft"]) for r in records if r["point"] == "NOM"} == {
        (select_points("NOM")[0].mach, select_points("NOM")[0].alt_ft)}
    s = json.loads((out / "summary.json").read_text())
    assert [p["label"] for p in s["points"]] == ["NOM", "C1"]
    assert sum(p["levels"][0]["per_hour"]["events"] for p in s["points"]) == s["levels"][0]["per_hour"]["events"]
    for name in ("soak_map.png", "soak_timeline.png", "report.html"):
        assert (out / name).stat().st_size > 0
    assert "<h2>Per point</h2>" in (out / "report.html").read_text()
    md = tmp_path / "soak.md"
    assert main(["report", str(out), "--markdown", str(md)]) == 0
    body = md.read_text()
    assert "at 2 points (NOM, C1)" in body and "## Per point" in body and "| C1 | 0.450 | 18000 |" in body
