"""report.drawing: deferrable calls run in order on one background thread inside the context,
as plain calls outside it, with their arguments snapshotted and their errors raised at the end."""
from __future__ import annotations

import os
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pytest

from f16mmae.report.drawing import deferrable, drawing_in_background

CALLS: list[tuple] = []


@deferrable(lambda a: Path(a["path"]))
def draw(summary: dict, path: str, tag: str = "plain") -> Path:
    CALLS.append((dict(summary), path, tag, threading.current_thread().name))
    if tag == "fail":
        raise ValueError(f"cannot draw {path}")
    Path(path).write_text(tag)
    return Path(path)


def test_outside_the_context_a_plain_call(tmp_path):
    CALLS.clear()
    out = draw({"a": 1}, str(tmp_path / "x.png"))
    assert out == tmp_path / "x.png" and out.read_text() == "plain"
    assert CALLS[0][3] == threading.current_thread().name


def test_inside_in_order_on_one_other_thread_with_snapshots(tmp_path):
    CALLS.clear()
    gate = threading.Event()
    summary = {"a": 1}
    with drawing_in_background():
        first = deferrable(lambda a: "queued")(lambda: gate.wait(10))()  # holds the thread
        paths = [draw(summary, str(tmp_path / f"{i}.png"), tag=f"t{i}") for i in range(3)]
        summary["added later"] = True       # after the call: not seen by the drawing
        assert first == "queued"
        assert paths == [tmp_path / f"{i}.png" for i in range(3)]
        assert not any(p.exists() for p in paths)   # not drawn yet: the thread is held
        gate.set()
    assert [c[2] for c in CALLS] == ["t0", "t1", "t2"]
    assert all(c[0] == {"a": 1} for c in CALLS)
    assert len({c[3] for c in CALLS}) == 1 and CALLS[0][3] != threading.current_thread().name
    assert [p.read_text() for p in paths] == ["t0", "t1", "t2"]


def test_an_error_is_raised_when_the_context_ends_after_the_rest_ran(tmp_path):
    CALLS.clear()
    with pytest.raises(ValueError, match="cannot draw"):
        with drawing_in_background():
            draw({}, str(tmp_path / "bad.png"), tag="fail")
            draw({}, str(tmp_path / "good.png"), tag="after")
    assert (tmp_path / "good.png").read_text() == "after"


@deferrable(lambda a: Path(a["path"]), alone=True)
def figure(path: str, tag: str, hold_s: float = 0.0) -> Path:
    time.sleep(hold_s)
    if tag == "fail":
        raise ValueError(f"cannot draw {path}")
    Path(path).write_text(f"{tag} {os.getpid()}")
    return Path(path)


@deferrable(lambda a: Path(a["path"]))
def page(path: str, figures: list) -> Path:  # reads the figures queued before it
    Path(path).write_text(" ".join(Path(f).read_text() for f in figures))
    return Path(path)


def test_figures_in_the_pools_processes_the_page_after_them(tmp_path):
    figs = [str(tmp_path / f"f{i}.png") for i in range(3)]
    with ProcessPoolExecutor(max_workers=2) as pool:
        with drawing_in_background(processes=pool):
            assert figure(figs[0], "a", 0.5) == Path(figs[0])
            figure(figs[1], "b", 0.5)
            out = page(str(tmp_path / "page.html"), figs[:2])
            figure(figs[2], "c")  # after the page: not waited for by it
    drawn = page.__wrapped__(str(tmp_path / "check"), figs)
    tags = drawn.read_text().split()
    assert tags[0::2] == ["a", "b", "c"]
    pids = {int(p) for p in tags[1::2]}
    assert os.getpid() not in pids and len(pids) >= 2  # two at once: each held 0.5 s
    assert out.read_text() == " ".join(tags[:4])  # the page saw both earlier figures


def test_a_figure_error_in_a_process_is_raised_when_the_context_ends(tmp_path):
    with ProcessPoolExecutor(max_workers=2) as pool:
        with pytest.raises(ValueError, match="cannot draw"):
            with drawing_in_background(processes=pool):
                figure(str(tmp_path / "bad.png"), "fail")
                page(str(tmp_path / "page.html"), [])
    assert (tmp_path / "page.html").exists()
