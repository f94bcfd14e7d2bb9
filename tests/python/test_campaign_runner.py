"""The campaign loop's tasks: chunks of consecutive runs (guided sizes), every record stored
once in plan order of completion, a failing run named with the runs before it kept, in process
each run's record stored before the next task flies, and a process pool storing the same
records as the inline executor."""
from __future__ import annotations

import math

import pytest

from f16mmae.campaign.engine.config import CampaignError
from f16mmae.campaign.engine.executor import InlineExecutor, make_executor
from f16mmae.campaign.engine.runner import CHUNK_MAX, chunks, execute, executor_workers
from f16mmae.campaign.engine.store import ResultsStore


def _specs(n: int) -> list[dict]:
    return [{"run_key": f"k{i:05d}", "i": i} for i in range(n)]


def square_run(spec: dict) -> dict:
    """A run whose record is a function of its spec alone (module-level: it crosses to workers)."""
    if spec.get("boom"):
        raise ArithmeticError(f"run {spec['i']} cannot fly")
    return {"run_key": spec["run_key"], "i": spec["i"], "square": spec["i"] ** 2, "timing": {}}


def test_chunks_keep_order_and_follow_the_guided_sizes():
    specs = _specs(3250)
    cut = chunks(specs, 2)
    assert [s for c in cut for s in c] == specs
    sizes = [len(c) for c in cut]
    left = 3250
    for k in sizes:  # each a quarter of a worker's share of what is left, 1..CHUNK_MAX
        assert k == max(1, min(CHUNK_MAX, left // 8))
        left -= k
    assert sizes[0] == CHUNK_MAX and sizes[-8:] == [1] * 8
    assert len(cut) < 3250 / 8
    assert [len(c) for c in chunks(_specs(5), 2)] == [1] * 5
    assert chunks([], 2) == []


def test_worker_counts():
    assert executor_workers(InlineExecutor()) == 1
    with make_executor(workers=2) as ex:
        assert executor_workers(ex) == 2


@pytest.mark.parametrize("workers", [1, 2])
def test_every_run_is_stored_once_with_its_record(tmp_path, workers):
    specs = _specs(150)
    with make_executor(workers=workers) as ex:
        done = execute(specs, ResultsStore(tmp_path), ex, square_run, describe=str, show_progress=False)
    stored = ResultsStore(tmp_path).records()
    assert sorted(r["run_key"] for r in stored) == [s["run_key"] for s in specs]
    assert all(r["square"] == r["i"] ** 2 for r in stored)
    assert len(done.executed_records) == 150 and done.resumed == 0


def test_a_failing_run_is_named_and_the_runs_before_it_are_stored(tmp_path):
    specs = _specs(40)
    specs[5]["boom"] = True  # inside the first chunk (40 // 4 = 10 runs)
    with pytest.raises(CampaignError, match=r"run 5 failed: ArithmeticError: run 5 cannot fly; the \d+ runs "
                                            r"finished so far are stored in"):
        execute(specs, ResultsStore(tmp_path), InlineExecutor(), square_run,
                describe=lambda s: f"run {s['i']}", show_progress=False)
    # its chunk's runs before it are stored, those after it were not flown (other chunks may be)
    stored = {r["i"] for r in ResultsStore(tmp_path).records()}
    assert {0, 1, 2, 3, 4} <= stored and not stored & set(range(5, 10))
    # the same command resumes: the stored runs are not flown again
    specs[5].pop("boom")
    done = execute(specs, ResultsStore(tmp_path), InlineExecutor(), square_run,
                   describe=lambda s: f"run {s['i']}", show_progress=False)
    assert done.resumed == len(stored) and len(done.executed_records) == 40 - len(stored)
    assert math.fsum(r["square"] for r in done.records) == sum(i * i for i in range(40))


def test_in_process_each_task_is_stored_before_the_next_is_flown(tmp_path):
    """--workers 1: a run sees every run before its task stored (progress and resume as it goes),
    and a failing run stops the campaign before any later task is flown."""
    specs = _specs(60)
    tasks = chunks(specs, 1)
    first_of_task = {task[0]["i"]: sum(len(t) for t in tasks[:n]) for n, task in enumerate(tasks)}
    seen = {}

    def run(spec):
        seen[spec["i"]] = len(ResultsStore(tmp_path).records())
        return square_run(spec)

    execute(specs, ResultsStore(tmp_path), InlineExecutor(), run, describe=str, show_progress=False)
    assert len(tasks) > 3 and all(seen[i] == stored for i, stored in first_of_task.items())
    later = tasks[2][0]["i"]
    failing = _specs(60)
    failing[later]["boom"] = True
    flown = []

    def run_until(spec):
        flown.append(spec["i"])
        return square_run(spec)

    with pytest.raises(CampaignError, match=f"run {later} failed"):
        execute(failing, ResultsStore(tmp_path / "failing"), InlineExecutor(), run_until,
                describe=lambda s: f"run {s['i']}", show_progress=False)
    assert flown == list(range(later + 1))
