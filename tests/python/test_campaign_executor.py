"""Executors and the progress bar (the campaign itself runs in test_campaign_single.py)."""
from __future__ import annotations

import io
import math

import pytest

from f16mmae.campaign.engine.executor import ExecutorError, InlineExecutor, check_scheduler_address, make_executor
from f16mmae.campaign.engine.progress import Progress


def test_local_pool_and_inline_give_the_same_results():
    with make_executor(workers=2) as ex:
        pooled = [f.result() for f in [ex.submit(math.factorial, n) for n in range(8)]]
    with make_executor(workers=1) as ex:
        assert isinstance(ex, InlineExecutor)
        inline = [ex.submit(math.factorial, n).result() for n in range(8)]
    assert pooled == inline == [math.factorial(n) for n in range(8)]


def test_inline_executor_delivers_exceptions_through_the_future():
    fut = InlineExecutor().submit(math.factorial, -1)
    with pytest.raises(ValueError):
        fut.result()


@pytest.mark.parametrize("bad", [0, -3])
def test_bad_worker_count(bad):
    with pytest.raises(ExecutorError, match=rf"--workers must lie in \[1, 1024\], got {bad}"):
        with make_executor(workers=bad):
            pass


@pytest.mark.parametrize("bad", ["localhost:8786", "http://host:1", "tcp://", ""])
def test_bad_scheduler_address_names_the_form(bad):
    with pytest.raises(ExecutorError, match="tcp://HOST:PORT"):
        check_scheduler_address(bad)
    assert check_scheduler_address("tcp://10.0.0.5:8786") == "tcp://10.0.0.5:8786"


def test_workers_and_scheduler_are_exclusive():
    with pytest.raises(ExecutorError, match="not both"):
        with make_executor(workers=2, scheduler="tcp://h:1"):
            pass


def test_progress_bar_counts_resumed_rate_and_time_left():
    out = io.StringIO()
    bar = Progress(10, "runs", already_done=4, stream=out, log_interval_s=0.0)
    for _ in range(3):
        bar.advance()
    assert bar.done == 7
    line = bar.line()
    assert "7/10" in line and "(4 resumed)" in line and "left" in line and "/s" in line
    for _ in range(5):  # never above total
        bar.advance()
    bar.close()
    text = out.getvalue()
    assert "10/10" in text.splitlines()[-1] and "elapsed" in text.splitlines()[-1]
    with pytest.raises(ValueError):
        Progress(3, already_done=4, stream=out)


def test_missing_dask_extra_is_a_clear_error(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed
    with pytest.raises(ExecutorError, match=r"pip install 'f16mmae\[dask\]'"):
        with make_executor(scheduler="tcp://127.0.0.1:8786"):
            pass
