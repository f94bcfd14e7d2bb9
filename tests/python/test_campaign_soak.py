"""The soak campaign: the false-declaration arithmetic against hand-made records, the Poisson
verdict, the flight condition a flight counts in (a hand-made track; a real pilotless flight
in severe air that leaves it, against the truth log's own air data), a short soak end to end
(common seeds across levels, summary, figures, report, Markdown, the reproduce command,
--check), resume after a partial run, and bad input."""
from __future__ import annotations

import json
import shlex

import pytest
from scipy import stats

from f16mmae.banks import load_bank
from f16mmae.campaign.engine import intervals
from f16mmae.campaign.engine.store import RECORDS_FILE, ResultsStore
from f16mmae.campaign.soak import SoakCampaign, run_soak
from f16mmae.campaign.soak.episodes import (CONDITION_ALT_FT, CONDITION_MACH, false_episodes, left_condition_s,
                                            level_rate)
from f16mmae.campaign.soak.report import soak_markdown, soak_page
from f16mmae.cli.main import main
from f16mmae.loop.flight import fly, scenario_from_dict

from campaign_support import CountingExecutor


def d(h, t):
    return {"hypothesis": h, "time_s": t}


# -- the arithmetic ------------------------------------------------------------------------------
def test_each_false_declaration_lasts_until_the_next_event_or_the_end():
    decl = [d("LF", 10.0), d("NONE", 11.5), d("AOA", 20.0), d("LS", 21.0), d("NONE", 22.25), d("RF", 590.0)]
    eps = false_episodes(decl, 600.0)
    assert [(e["hypothesis"], e["time_s"], e["duration_s"], e["end"], e["replaced_by"]) for e in eps] == [
        ("LF", 10.0, 1.5, "backed out", None), ("AOA", 20.0, 1.0, "replaced", "LS"),
        ("LS", 21.0, 1.25, "backed out", None), ("RF", 590.0, 10.0, "flight end", None)]
    assert false_episodes([], 600.0) == []
    with pytest.raises(ValueError, match="ordered"):
        false_episodes([d("LF", 5.0), d("NONE", 4.0)], 600.0)
    with pytest.raises(ValueError, match="ordered"):
        false_episodes([d("LF", 700.0)], 600.0)


def _record(decl, duration_s=600.0):
    eps = false_episodes(decl, duration_s)
    return {"episodes": eps, "false_declarations": len(eps), "failure_free_s": duration_s}


def test_per_hour_rate_interval_and_verdicts_of_hand_made_records():
    # three 600-s flights = 0.5 h; 4 false declarations -> 8 per hour
    recs = [_record([d("LF", 1.0), d("NONE", 2.0), d("LF", 3.0)]), _record([]),
            _record([d("AOA", 5.0), d("NONE", 5.5), d("RF", 6.0), d("NONE", 9.0)])]
    lv = level_rate(recs, goal_per_h=0.0)
    assert lv["flights"] == 3 and lv["hours"] == pytest.approx(0.5)
    ph = lv["per_hour"]
    assert ph["events"] == 4 and ph["rate"] == pytest.approx(8.0)
    # the exact interval's bounds mu solve P(X >= 4 | mu) = 0.025 and P(X <= 4 | mu) = 0.025
    lo_mu, hi_mu = ph["ci95"][0] * 0.5, ph["ci95"][1] * 0.5
    assert stats.poisson.sf(3, lo_mu) == pytest.approx(0.025, abs=1e-5)
    assert stats.poisson.cdf(4, hi_mu) == pytest.approx(0.025, abs=1e-5)
    assert ph["verdict"] == "not met"
    assert lv["hypotheses"] == {"LF": 2, "AOA": 1, "RF": 1}
    assert lv["flights_with_false_declaration"] == 2
    assert lv["episodes_by_end"] == {"backed out": 3, "replaced": 0, "flight end": 1}
    # durations 1.0, 597.0 (LF at 3 s to the end), 0.5, 3.0: median (1.0 + 3.0) / 2
    assert lv["duration_s"] == {"median": 2.0, "max": 597.0}
    assert lv["first_declaration_s"] == {"median": 3.0, "min": 1.0}  # flights 1 and 3 first at 1 s and 5 s
    assert level_rate(recs, 19.0)["per_hour"]["verdict"] == "consistent"  # 8 <= 19 < 20.48
    assert level_rate(recs, 21.0)["per_hour"]["verdict"] == "demonstrated"


def test_a_flight_counts_until_the_first_second_off_its_flight_condition():
    track = [[0.0, 0.40, 20000.0], [1.0, 0.45, 21000.0], [2.0, 0.40 + CONDITION_MACH + 0.01, 20000.0],
             [3.0, 0.40, 20000.0]]
    assert left_condition_s(track, 0.40, 20000.0, level_flight=True) == 2.0   # back on it later: still left
    climbed = [[0.0, 0.40, 20000.0], [1.0, 0.40, 20000.0 - CONDITION_ALT_FT - 1.0]]
    assert left_condition_s(climbed, 0.40, 20000.0, level_flight=True) == 1.0
    assert left_condition_s(climbed, 0.40, 20000.0, level_flight=False) is None   # maneuvers: finite is enough
    crashed = [[0.0, 0.40, 20000.0], [1.0, float("nan"), float("nan")]]
    assert left_condition_s(crashed, 0.40, 20000.0, level_flight=False) == 1.0
    assert left_condition_s(track[:2], 0.40, 20000.0, level_flight=True) is None
    # the level's hours and declarations are those flown on the condition; the rest reported apart
    left = {**_record([d("LF", 10.0), d("NONE", 11.0)], duration_s=300.0), "left_condition_s": 300.0,
            "declarations_after_leaving": [d("ROL", 310.0), d("NONE", 312.0), d("RUD", 320.0)]}
    lv = level_rate([left, _record([])], goal_per_h=0.0)
    assert lv["hours"] == pytest.approx(0.25) and lv["per_hour"]["events"] == 1
    assert lv["flights_left_condition"] == 1 and lv["declarations_after_leaving"] == 2


def test_a_pilotless_flight_in_severe_air_leaves_the_condition_and_counts_until_then(tmp_path):
    # campaign seed 4, flight 0: pilotless at Mach 0.3, 10,000 ft in severe air, the FCS on the
    # raw measurements (no estimator in the loop); it leaves the condition within two minutes
    cfg = SoakCampaign(hours=120 / 3600, duration_s=120.0, turbulence="severe", seed=4, mach=0.3, alt_ft=10000.0,
                       feedback="raw")
    done = run_soak(cfg, tmp_path / "soak", CountingExecutor(), show_progress=False)
    (r,) = done.records
    left = r["left_condition_s"]
    assert left is not None and 0.0 < left < 120.0
    # the same flight's truth log: its ideal air data at whole seconds, first off the condition at `left`
    flown = fly(scenario_from_dict(r["scenario"]), load_bank("tuned")[2], estimator_options=r["estimator"],
                record_series=True)
    log = flown.series["truth_log"]
    seconds = log["time_s"][::64]
    air = log["air_data_ideal"][::64]
    off = (abs(air[:, 0] - 0.3) > CONDITION_MACH) | (abs(air[:, 1] - 10000.0) > CONDITION_ALT_FT)
    assert seconds[off.argmax()] == left and not off[seconds < left].any()
    assert flown.declarations == r["declarations"]
    # counted up to `left`, the rest apart
    assert r["failure_free_s"] == left
    assert all(e["time_s"] < left for e in r["episodes"])
    assert r["declarations"] == [x for x in r["declarations"] if x["time_s"] < left] + r["declarations_after_leaving"]
    assert all(x["time_s"] >= left for x in r["declarations_after_leaving"])
    assert r["false_declarations"] == sum(1 for x in r["declarations"] if x["time_s"] < left and x["hypothesis"] != "NONE")
    s = json.loads((tmp_path / "soak" / "summary.json").read_text())
    (lv,) = s["levels"]
    assert lv["hours"] == pytest.approx(left / 3600.0) and lv["flights_left_condition"] == 1
    assert s["left_condition"][0]["left_condition_s"] == left
    assert s["left_condition"][0]["command"].startswith("f16mmae run ")
    page, text = soak_page(tmp_path / "soak", s), soak_markdown(s)
    assert "Flights that left the flight condition" in page and s["left_condition"][0]["command"] in text


def test_poisson_verdict():
    # 0 events in 1 h: upper bound -ln(0.025) = 3.689 per hour
    assert intervals.poisson_verdict(0, 1.0, 0.0) == "consistent"
    assert intervals.poisson_verdict(0, 1.0, 3.6) == "consistent"
    assert intervals.poisson_verdict(0, 1.0, 3.7) == "demonstrated"
    assert intervals.poisson_verdict(2, 1.0, 1.0) == "not met"
    with pytest.raises(ValueError, match="exposure"):
        intervals.poisson_verdict(0, 0.0, 1.0)
    with pytest.raises(ValueError, match=">= 0"):
        intervals.poisson_verdict(0, 1.0, -1.0)


# -- a short soak, end to end ----------------------------------------------------------------------
def test_short_soak_end_to_end_and_resume(tmp_path):
    out = tmp_path / "soak"
    # 3 flights of 8 s per level; moderate turbulence makes the light-tuned bank false-alarm
    cfg = SoakCampaign(hours=24 / 3600, duration_s=8.0, turbulence="none,moderate", seed=3)
    assert cfg.flights == 3
    ex = CountingExecutor()
    done = run_soak(cfg, out, ex, show_progress=False)
    assert ex.submitted == 6 and len(done.records) == 6
    s = json.loads((out / "summary.json").read_text())
    assert s["kind"] == "soak" and [lv["level"] for lv in s["levels"]] == ["none", "moderate"]
    # common random numbers: flight n has the same seed at both levels, distinct across n
    seeds = {(r["level"], r["run_index"]): r["seed"] for r in done.records}
    assert all(seeds[("none", n)] == seeds[("moderate", n)] for n in range(3))
    assert len({seeds[("none", n)] for n in range(3)}) == 3
    for r in done.records:
        assert r["scenario"]["failures"] == [] and r["scenario"]["duration_s"] == 8.0
        assert r["scenario"]["turbulence"] == r["level"]
    for lv in s["levels"]:
        recs = [r for r in done.records if r["level"] == lv["level"]]
        assert lv["per_hour"]["events"] == sum(r["false_declarations"] for r in recs)
        assert lv["hours"] == pytest.approx(24 / 3600)
        assert lv["per_hour"]["goal"] == 0.0
    moderate = s["levels"][1]
    assert moderate["per_hour"]["events"] > 0, "moderate turbulence made no false declaration to drill into"
    assert s["goals_met"] is False
    flagged = {(e["level"], e["run_index"]) for e in s["not_clean"]}
    assert flagged == {(r["level"], r["run_index"]) for r in done.records if r["false_declarations"]}
    for name in s["figures"].values():
        assert (out / name).stat().st_size > 0
    # the reproduce command flies the flight again, declaration for declaration
    entry = next(e for e in s["not_clean"] if e["level"] == "moderate")
    argv = shlex.split(entry["command"])
    assert argv[:2] == ["f16mmae", "run"] and "--turbulence" in argv and "moderate" in argv
    assert main(argv[1:] + ["--out", str(tmp_path / "again")]) == 0
    flown = json.loads((tmp_path / "again" / "run.json").read_text())
    assert flown["declarations"] == entry["declarations"]

    # resume: cut the store to its first two records, then a longer soak keeps what is stored
    lines = (out / RECORDS_FILE).read_text().splitlines(keepends=True)
    (out / RECORDS_FILE).write_text("".join(lines[:2]))
    longer = SoakCampaign(hours=32 / 3600, duration_s=8.0, turbulence="none,moderate", seed=3)
    ex2 = CountingExecutor()
    again = run_soak(longer, out, ex2, show_progress=False)
    assert ex2.submitted == 8 - 2 and len(again.records) == 8
    before = {r["run_key"]: r["declarations"] for r in done.records}
    for r in again.records:
        if r["run_key"] in before:
            assert r["declarations"] == before[r["run_key"]]
    assert len(ResultsStore(out).records()) == 8


def test_cli_soak_check_report_and_markdown(tmp_path, capsys):
    out = tmp_path / "cli"
    argv = ["campaign", "soak", "--hours", str(16 / 3600), "--flight-s", "8", "--turbulence", "moderate",
            "--workers", "1", "--quiet", "--out", str(out)]
    code = main(argv + ["--check"])
    text = capsys.readouterr().out
    s = json.loads((out / "summary.json").read_text())
    assert code == (0 if s["goals_met"] else 1)
    assert "false declarations per flight hour" in text and "moderate:" in text
    assert s["command"].startswith("f16mmae campaign soak --hours")
    page = (out / "report.html").read_text()
    assert "f16mmae soak campaign" in page and "soak: failure-free flights, trim, no pilot (no maneuvers)" in page
    md = tmp_path / "soak.md"
    assert main(["report", str(out), "--markdown", str(md)]) == 0
    body = md.read_text()
    assert "| moderate | 2 |" in body and "False declarations per flight hour" in body


@pytest.mark.parametrize("args, message", [
    (["--flight-s", "4000"], "--flight-s"),
    (["--hours", "0"], "--hours"),
    (["--turbulence", "light,light"], "twice"),
    (["--turbulence", "light,stormy"], "stormy"),
    (["--mach", "0.5"], "give --mach and --alt-ft together"),
    (["--alt-ft", "15000"], "give --mach and --alt-ft together"),
    (["--mach", "0.9", "--alt-ft", "15000"], "--mach '0.9' must be <= 0.8"),
    (["--mach", "0.5", "--alt-ft", "nan"], "--alt-ft 'nan' must be finite"),
])
def test_cli_soak_bad_input(tmp_path, capsys, args, message):
    out = tmp_path / "bad"
    assert main(["campaign", "soak", "--workers", "1", "--out", str(out), *args]) == 2
    assert message in capsys.readouterr().err
    assert not (out / RECORDS_FILE).exists()


def test_cli_soak_at_a_flight_condition_flies_every_flight_there(tmp_path, capsys):
    """--mach/--alt-ft: every flight starts trimmed there (the scenario and its reproduce command
    say so), the summary names it, and a profile's maneuvers start from it."""
    out = tmp_path / "off"
    argv = ["campaign", "soak", "--hours", str(16 / 3600), "--flight-s", "8", "--mach", "0.5", "--alt-ft", "15000",
            "--workers", "1", "--quiet", "--out", str(out)]
    assert main(argv) == 0
    s = json.loads((out / "summary.json").read_text())
    assert (s["mach"], s["alt_ft"]) == (0.5, 15000.0)
    records = ResultsStore(out).records()
    assert len(records) == 2 and all((r["scenario"]["mach"], r["scenario"]["alt_ft"]) == (0.5, 15000.0)
                                     for r in records)
    cfg = SoakCampaign(hours=1.0, duration_s=540.0, profile="tour", mach=0.5, alt_ft=15000.0).validate()
    from f16mmae.campaign.soak.campaign import flight_maneuvers
    mans = flight_maneuvers(cfg, None)
    assert mans[0].startswith("climb@10") and "19000ft" in mans[0] and any("0.6mach" in m for m in mans)
    with pytest.raises(Exception, match="--mach and --alt-ft together"):
        SoakCampaign(hours=1.0, mach=0.5).validate()
