"""The results store: append, resume (skip stored keys), half-written last line."""
from __future__ import annotations

import json

import pytest

from f16mmae.campaign.engine.store import RECORDS_FILE, ResultsStore, StoreError, run_key


def _rec(i: int) -> dict:
    return {"run_key": run_key({"i": i}), "case": "LS", "run_index": i, "outcome": "correct"}


def test_run_key_is_canonical_and_distinct():
    assert run_key({"a": 1, "b": [1, 2]}) == run_key({"b": [1, 2], "a": 1})
    assert run_key({"a": 1}) != run_key({"a": 2})


def test_append_then_read_back_in_order(tmp_path):
    with ResultsStore(tmp_path / "c") as store:
        assert store.records() == [] and store.keys() == set()
        for i in range(3):
            store.append(_rec(i))
        # each line reaches the file as it is appended (a killed campaign keeps it)
        assert [r["run_index"] for r in ResultsStore(tmp_path / "c").records()] == [0, 1, 2]
    again = ResultsStore(tmp_path / "c")
    assert [r["run_index"] for r in again.records()] == [0, 1, 2]
    assert again.keys() == {_rec(i)["run_key"] for i in range(3)}


def test_half_written_last_line_is_cut_and_appends_continue(tmp_path):
    with ResultsStore(tmp_path) as store:
        store.append(_rec(0))
        store.append(_rec(1))
    full = json.dumps(_rec(2))
    with open(tmp_path / RECORDS_FILE, "a") as f:  # killed in the middle of a write
        f.write(full[: len(full) // 2])
    store = ResultsStore(tmp_path)
    assert [r["run_index"] for r in store.records()] == [0, 1]
    assert store.repaired_bytes == len(full) // 2
    with store:
        store.append(_rec(2))
    assert [r["run_index"] for r in ResultsStore(tmp_path).records()] == [0, 1, 2]


def test_half_written_only_line(tmp_path):
    (tmp_path / RECORDS_FILE).write_text('{"run_key": "ab')
    store = ResultsStore(tmp_path)
    assert store.records() == []
    with store:
        store.append(_rec(5))
        assert [r["run_index"] for r in store.records()] == [5]


def test_corrupt_middle_line_is_refused_with_its_line_number(tmp_path):
    (tmp_path / RECORDS_FILE).write_text(json.dumps(_rec(0)) + "\nnot json\n" + json.dumps(_rec(1)) + "\n")
    with pytest.raises(StoreError, match=r"runs.jsonl:2"):
        ResultsStore(tmp_path).records()


def test_record_without_key_is_refused(tmp_path):
    with pytest.raises(ValueError, match="run_key"):
        ResultsStore(tmp_path).append({"case": "LS"})


def test_fsync_at_most_once_per_interval_and_on_close(tmp_path, monkeypatch):
    import os
    synced = []
    real = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (synced.append(fd), real(fd)))
    clock = [100.0]
    monkeypatch.setattr("f16mmae.campaign.engine.store.time.monotonic", lambda: clock[0])
    with ResultsStore(tmp_path, sync_interval_s=1.0) as store:
        for i in range(5):  # within one second: no fsync yet
            store.append(_rec(i))
            clock[0] += 0.1
        assert synced == []
        clock[0] += 0.6  # 1.1 s since the handle opened
        store.append(_rec(5))
        assert len(synced) == 1
        store.append(_rec(6))
        assert len(synced) == 1
    assert len(synced) == 2  # closing syncs the rest
    assert [r["run_index"] for r in ResultsStore(tmp_path).records()] == list(range(7))
