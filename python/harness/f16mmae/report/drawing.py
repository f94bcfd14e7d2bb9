"""Figures and report pages drawn on a background thread while the caller goes on.

``f16mmae campaign paper`` flies three campaigns one after the other on one process pool; the
figures and report page of one are drawn in the parent (matplotlib, a few seconds) while the
pool's workers would otherwise wait.  Within :func:`drawing_in_background`, every call of a
function marked :func:`deferrable` (the campaigns' figures, ``report.page.render_report``) is
queued to one background thread, which runs the calls one at a time in the order they were
made (so a page is written after its figures, and pyplot is used by one thread only), and
returns at once what the function will return (its output path).  Outside the context a
deferrable function is an ordinary call.

Arguments are snapshotted when queued: a ``dict`` or ``list`` argument is copied one level
deep (a caller adding a key to a summary after the call does not change the drawing; the
records themselves are not changed after a campaign).  On leaving the context every queued
call is waited for, and the first error any raised is raised again there.

With ``drawing_in_background(processes=pool)`` (a ``ProcessPoolExecutor``: the campaign's own,
idle between its parts and at the end), a function marked ``deferrable(..., alone=True)`` -- a
figure: it writes its own file from its arguments alone -- is drawn in one of the pool's
processes instead, several at once; every other call (a report page, which reads the figures)
still runs on the thread, after every call queued before it has finished.  The parent's CPU
then draws nothing, and the figures of the command's last part are drawn side by side on the
idle workers instead of one after the other.  A figure is the same file either way (the same
function on the same arguments).
"""
from __future__ import annotations

import contextlib
import functools
import importlib
import inspect
from collections.abc import Callable
from concurrent.futures import Executor, Future, ThreadPoolExecutor, wait

_drawer: ThreadPoolExecutor | None = None
_processes: Executor | None = None
_queued: list[Future] = []
_in_processes: list[Future] = []  # figures in the pool that no thread call has waited for yet


def _snapshot(value):
    if isinstance(value, dict):
        return dict(value)
    if isinstance(value, list):
        return list(value)
    return value


def deferrable(result: Callable[[dict], object], alone: bool = False):
    """Mark a drawing function: ``result(arguments)`` (its bound arguments by name) gives what
    it returns, without drawing (e.g. ``lambda a: Path(a["path"])``); ``alone``: it needs
    nothing but its arguments and writes only its own file (a figure), so it may run in
    another process (module docstring)."""
    def mark(fn):
        signature = inspect.signature(fn)

        @functools.wraps(fn)
        def call(*args, **kwargs):
            if _drawer is None:
                return fn(*args, **kwargs)
            bound = signature.bind(*args, **kwargs)
            bound.apply_defaults()
            arguments = {k: _snapshot(v) for k, v in bound.arguments.items()}
            if alone and _processes is not None:
                future = _processes.submit(_call_undecorated, fn.__module__, fn.__qualname__, arguments)
                _in_processes.append(future)
            else:
                future = _drawer.submit(_after, list(_in_processes), fn, arguments)
                _in_processes.clear()
            _queued.append(future)
            return result(arguments)
        return call
    return mark


def _call_undecorated(module: str, qualname: str, arguments: dict):
    """In a pool process: the deferrable function ``module.qualname`` itself, called."""
    marked = importlib.import_module(module)
    for name in qualname.split("."):
        marked = getattr(marked, name)
    return marked.__wrapped__(**arguments)


def _after(earlier: list[Future], fn: Callable, arguments: dict):
    wait(earlier)  # their errors are raised when the context ends
    return fn(**arguments)


@contextlib.contextmanager
def drawing_in_background(processes: Executor | None = None):
    """Within: deferrable calls run on one background thread, figures in ``processes`` if
    given (module docstring)."""
    global _drawer, _processes
    if _drawer is not None:  # nested: the outer context waits
        yield
        return
    _drawer = ThreadPoolExecutor(max_workers=1, thread_name_prefix="f16mmae-drawing")
    _processes = processes
    try:
        yield
    finally:
        drawer, _drawer, _processes = _drawer, None, None
        queued = list(_queued)
        _queued.clear()
        _in_processes.clear()
        drawer.shutdown(wait=True)
        wait(queued)  # the figures in processes too, even when the body raised
    for future in queued:
        error = None if future.cancelled() else future.exception()
        if error is not None:
            raise error
