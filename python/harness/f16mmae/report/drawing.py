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
"""
from __future__ import annotations

import contextlib
import functools
import inspect
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

_drawer: ThreadPoolExecutor | None = None
_queued: list[Future] = []


def _snapshot(value):
    if isinstance(value, dict):
        return dict(value)
    if isinstance(value, list):
        return list(value)
    return value


def deferrable(result: Callable[[dict], object]):
    """Mark a drawing function: ``result(arguments)`` (its bound arguments by name) gives what
    it returns, without drawing (e.g. ``lambda a: Path(a["path"])``)."""
    def mark(fn):
        signature = inspect.signature(fn)

        @functools.wraps(fn)
        def call(*args, **kwargs):
            if _drawer is None:
                return fn(*args, **kwargs)
            bound = signature.bind(*args, **kwargs)
            bound.apply_defaults()
            arguments = {k: _snapshot(v) for k, v in bound.arguments.items()}
            _queued.append(_drawer.submit(fn, **arguments))
            return result(arguments)
        return call
    return mark


@contextlib.contextmanager
def drawing_in_background():
    """Within: deferrable calls run on one background thread (module docstring)."""
    global _drawer
    if _drawer is not None:  # nested: the outer context waits
        yield
        return
    _drawer = ThreadPoolExecutor(max_workers=1, thread_name_prefix="f16mmae-drawing")
    try:
        yield
    finally:
        drawer, _drawer = _drawer, None
        queued = list(_queued)
        _queued.clear()
        drawer.shutdown(wait=True)
    for future in queued:
        error = future.exception()
        if error is not None:
            raise error
