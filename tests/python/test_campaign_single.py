"""The single campaign end to end on the REAL truth model and estimator (small plans):
seeds, summary == stored records, resume after a kill, same results on any executor."""
from __future__ import annotations

import json

import pytest

from f16mmae.campaign.engine import scoring
from f16mmae.campaign.engine.executor import InlineExecutor, make_executor
from f16mmae.banks import load_bank
from f16mmae.campaign.engine.failure_runs import plan, run_seed
from f16mmae.campaign.engine.config import CampaignError
from f16mmae.campaign.single import SingleCampaign, run_campaign
from f16mmae.campaign.single.campaign import case_summary, first_declaration
from f16mmae.campaign.engine.store import RECORDS_FILE, ResultsStore

from campaign_support import CountingExecutor

SMALL = SingleCampaign(runs=2, seed=4, cases=("NONE", "PIT"), baseline=None,
                       failure_time_s=2.0, duration_s=4.5)


def test_run_seeds_are_deterministic_distinct_and_positive():
    seeds = {(c, n): run_seed(1, c, n) for c in ("NONE", "LS", "PIT") for n in range(50)}
    assert all(s >= 1 for s in seeds.values())
    assert len(set(seeds.values())) == len(seeds)
    assert run_seed(1, "LS", 3) == run_seed(1, "LS", 3) != run_seed(2, "LS", 3)


def test_first_declaration_is_reported_beside_the_score_not_in_its_place():
    def rec(case, t_f, decl):
        return {"case": case, "failure_time_s": t_f, "outcome": scoring.score_run(case, t_f, decl)["outcome"],
                "declarations": decl}
    d = lambda h, t: {"hypothesis": h, "time_s": t}  # noqa: E731
    departed = rec("LS", 3.0, [d("LS", 3.9), d("LS+AOA", 5.0)])   # right first, then a dual
    early = rec("LS", 3.0, [d("RS", 2.0), d("NONE", 2.5), d("LS", 3.5)])  # a false alarm before the onset
    wrong_first = rec("LS", 3.0, [d("RS", 3.5), d("LS", 4.0)])
    assert [first_declaration(r) for r in (departed, early, wrong_first)] == ["LS", "LS", "RS"]
    assert first_declaration(rec("NONE", None, [])) == "NONE"
    assert first_declaration(rec("NONE", None, [d("YAW", 6.0), d("NONE", 7.0)])) == "YAW"
    for r in (departed, early, wrong_first):
        r["false_alarm"], r["latency_s"] = False, None
    s = case_summary("LS", [departed, early, wrong_first])
    assert (s["first_declared_correct"], s["correct"], s["wrong"]) == (2, 2, 1)


def _strip(records):
    keep = ("run_key", "case", "run_index", "seed", "declarations", "outcome", "latency_s",
            "false_alarm", "p_injected", "bank_hash")
    return sorted(({k: r[k] for k in keep} for r in records), key=lambda r: r["run_key"])


@pytest.mark.slow
def test_summary_resume_and_executors(tmp_path):
    first = run_campaign(SMALL, tmp_path / "a", CountingExecutor(), show_progress=False, measure_cost=False)
    assert first.executed == 4 and first.resumed == 0
    stored = ResultsStore(tmp_path / "a").records()
    assert len(stored) == 4
    # every record carries what reproduces it
    for r in stored:
        assert r["seed"] >= 1 and r["bank_hash"] and r["version"] and r["scenario"]["seed"] == r["seed"]
    # summary numbers match the stored records
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert summary["kind"] == "single" and summary["runs_per_case"] == 2
    for case in summary["cases"]:
        recs = [r for r in stored if r["case"] == case["case"]]
        assert {k: v for k, v in case.items() if k != "first_declared_correct"} == \
            scoring.summarize_case(case["case"], recs)
        assert case["first_declared_correct"] == sum(1 for r in recs if first_declaration(r) == case["case"])
    assert sum(c["runs"] for c in summary["cases"]) == 4
    assert all(r["outcome"] in scoring.OUTCOMES for r in stored)

    # kill half way: keep one full record and half of the next line, then resume
    path = tmp_path / "a" / RECORDS_FILE
    lines = path.read_text().splitlines(keepends=True)
    path.write_text(lines[0] + lines[1][: len(lines[1]) // 2])
    ex = CountingExecutor()
    again = run_campaign(SMALL, tmp_path / "a", ex, show_progress=False, measure_cost=False)
    assert (again.resumed, again.executed, ex.submitted) == (1, 3, 3)
    assert _strip(ResultsStore(tmp_path / "a").records()) == _strip(stored)
    # same arguments once more: nothing to run
    ex = CountingExecutor()
    assert run_campaign(SMALL, tmp_path / "a", ex, show_progress=False, measure_cost=False).executed == 0 and ex.submitted == 0

    # a process pool gives the same records
    with make_executor(workers=2) as pool:
        run_campaign(SMALL, tmp_path / "b", pool, show_progress=False, measure_cost=False)
    assert _strip(ResultsStore(tmp_path / "b").records()) == _strip(stored)


@pytest.mark.slow
def test_dask_executor_gives_the_same_records(tmp_path):
    import distributed  # the 'dask' extra, installed by make build: a missing one fails here
    cfg = SingleCampaign(runs=1, seed=4, cases=("PIT",), baseline=None, failure_time_s=2.0, duration_s=4.5)
    run_campaign(cfg, tmp_path / "local", InlineExecutor(), show_progress=False, measure_cost=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        with make_executor(scheduler=cluster.scheduler_address) as ex:
            run_campaign(cfg, tmp_path / "dask", ex, show_progress=False, measure_cost=False)
    assert _strip(ResultsStore(tmp_path / "dask").records()) == _strip(ResultsStore(tmp_path / "local").records())


def test_the_failure_time_moves_the_failure_and_keeps_the_flight_after_it():
    """``--failure-time S``: the failure at S s, the flight 5 s beyond it (the default's 3 of 8)."""
    from f16mmae.cli import campaign_single
    from f16mmae.cli.main import build_parser
    args = build_parser().parse_args(["campaign", "single", "--failure-time", "20", "--cases", "LS"])
    cfg = campaign_single.config_from_args(args)
    assert (cfg.failure_time_s, cfg.duration_s) == (20.0, 25.0)
    default = campaign_single.config_from_args(build_parser().parse_args(["campaign", "single"]))
    assert (default.failure_time_s, default.duration_s) == (3.0, 8.0)
    spec = plan(cfg, {"tuned": ("tuned", load_bank("tuned")[2])})[0]
    assert spec["scenario"]["duration_s"] == 25.0
    assert [(f["name"], f["time_s"]) for f in spec["scenario"]["failures"]] == [("LS", 20.0)]



def test_the_failure_jitter_spreads_each_runs_failure_by_its_seed():
    """``--failure-jitter J``: run n of case c fails at failure_time_s + J x_{c,n}, x in [0, 1) from
    the run's seed alone, and flies as long after it as without; J = 0 is the plan as before."""
    from f16mmae.campaign.engine.failure_runs import failure_offset
    bank = load_bank("tuned")[2]
    assert failure_offset(123, 0.0) == 0.0
    assert failure_offset(123, 1.0) == failure_offset(123, 1.0) == 2.0 * failure_offset(123, 0.5)
    base = SingleCampaign(runs=8, seed=4, cases=("NONE", "RUD"), baseline=None)
    spread = SingleCampaign(runs=8, seed=4, cases=("NONE", "RUD"), baseline=None, failure_jitter_s=1.0)
    plain, jittered = plan(base, {"t": ("tuned", bank)}), plan(spread, {"t": ("tuned", bank)})
    offsets = []
    for a, b in zip(plain, jittered):
        assert a["seed"] == b["seed"]
        offset = failure_offset(b["seed"], 1.0)
        assert 0.0 <= offset < 1.0
        assert b["scenario"]["duration_s"] == pytest.approx(8.0 + offset)
        if a["case"] == "RUD":
            assert a["scenario"]["failures"][0]["time_s"] == 3.0
            assert b["scenario"]["failures"][0]["time_s"] == pytest.approx(3.0 + offset)
            offsets.append(offset)
        assert a["run_key"] != b["run_key"]
    assert max(offsets) - min(offsets) > 0.3   # spread, not one instant
    with pytest.raises(CampaignError, match="--failure-jitter 61 must lie in"):
        SingleCampaign(failure_jitter_s=61.0).validate()
