"""Executors for campaigns, all behind ``concurrent.futures.Executor``.

* local (default): ``ProcessPoolExecutor(max_workers=W)``, W = the machine's cores;
  ``--workers 1`` runs in process (``InlineExecutor``), handy for profiling and tests.
* cluster: ``--scheduler tcp://HOST:PORT`` -> ``distributed.Client(address).get_executor()``
  (Dask's ``concurrent.futures`` adapter).  ``distributed`` is an optional extra
  (``pip install 'f16mmae[dask]'``), imported only when a scheduler is asked for.  The
  workers must have the same f16mmae version installed (the records carry it).

Each task is one run: a pure function of its spec (seeds included), so the results do
not depend on which executor ran them or in what order they finished.

Local pool workers die with the campaign: each runs a watchdog thread that ends the worker
within ``WATCHDOG_PERIOD_S`` once its parent is gone (killed, even by ``kill -9``), so no
orphaned worker goes on flying runs nobody will store.
"""
from __future__ import annotations

import contextlib
import os
import re
import threading
import time
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from typing import Callable, Iterator

from ...errors import F16mmaeError

_SCHEDULER_RE = re.compile(
    r"^(?:(?:tcp|tls|ucx|ws|wss)://(?:\[[0-9A-Fa-f:.]+\]|[^\s/:\[\]]+)(?::\d+)?/?|inproc://\S+)$"
)


#: The most local worker processes a pool starts.
WORKERS_MAX = 1024
#: How often a pool worker checks that the campaign process that started it is alive.
WATCHDOG_PERIOD_S = 0.2


class ExecutorError(F16mmaeError):
    """An executor cannot be set up (bad worker count, bad address, missing extra)."""


class InlineExecutor(Executor):
    """Runs each task at submit time in this process (``--workers 1``)."""

    def submit(self, fn: Callable, /, *args, **kwargs) -> Future:
        fut: Future = Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 -- delivered through the future
            fut.set_exception(exc)
        return fut


def die_with_parent(parent_pid: int) -> None:
    """Pool worker initializer: a daemon thread that exits this process (status 1) as soon as
    its parent is no longer ``parent_pid`` (the parent died and the worker was re-parented)."""
    def watch() -> None:
        while os.getppid() == parent_pid:
            time.sleep(WATCHDOG_PERIOD_S)
        os._exit(1)

    if os.getppid() != parent_pid:
        os._exit(1)
    threading.Thread(target=watch, name="f16mmae-parent-watchdog", daemon=True).start()


def default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def check_scheduler_address(address: str) -> str:
    if not _SCHEDULER_RE.match(address):
        raise ExecutorError(
            f"scheduler address {address!r} is not of the form tcp://HOST:PORT "
            f"(also accepted: tls://, ucx://, ws://, wss://, inproc://)"
        )
    return address


@contextlib.contextmanager
def make_executor(workers: int | None = None, scheduler: str | None = None) -> Iterator[Executor]:
    """The executor a campaign runs on, closed (and its pool shut down) on exit."""
    if workers is not None and scheduler is not None:
        raise ExecutorError("give either a worker count or a scheduler address, not both")
    if scheduler is not None:
        check_scheduler_address(scheduler)
        try:
            import distributed  # optional extra
        except ImportError:
            raise ExecutorError(
                "--scheduler needs Dask's 'distributed' package, which is not installed; "
                "install it with: pip install 'f16mmae[dask]'  (or: pip install distributed)"
            ) from None
        try:
            client = distributed.Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise ExecutorError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from None
        try:
            with client.get_executor() as ex:
                yield ex
        finally:
            client.close()
        return
    n = default_workers() if workers is None else workers
    if not 1 <= n <= WORKERS_MAX:
        raise ExecutorError(f"--workers must lie in [1, {WORKERS_MAX}], got {n}")
    if n == 1:
        yield InlineExecutor()
        return
    pool = ProcessPoolExecutor(max_workers=n, initializer=die_with_parent, initargs=(os.getpid(),))
    try:
        yield pool
    except BaseException:
        # Interrupted or failed: do not wait for the queued runs (the store keeps the
        # finished ones; a restart resumes).
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    else:
        pool.shutdown(wait=True)
