"""Output paths, checked before the work that fills them: a command that would fail to write
its results says so at once, instead of after a flight or a campaign.

``writable_dir(path, option)`` creates the directory (and its parents) and writes a probe file
in it; ``writable_file(path, option)`` checks that ``path`` is not a directory and that its
folder is writable.  Both raise :class:`OutputError` naming the option, the path and why:
an existing file where a directory is wanted, a path under a file, no permission, a
read-only file system.
"""
from __future__ import annotations

import tempfile
from pathlib import Path

from .errors import F16mmaeError


class OutputError(F16mmaeError):
    """An output path cannot be written; the message names the option, the path and why."""


def _under_a_file(p: Path) -> Path | None:
    """The nearest existing ancestor of ``p`` (``p`` included) when it is not a directory."""
    for q in (p, *p.parents):
        if q.exists():
            return None if q.is_dir() else q
    return None


def _prepare(directory: Path, option: str, path: str | Path) -> None:
    """Create ``directory`` and write a probe in it; OutputError naming ``option path`` if not."""
    blocker = _under_a_file(directory)
    if blocker is not None:
        raise OutputError(f"{option} {str(path)!r} lies under {str(blocker)!r}, which is a file, not a directory")
    try:
        directory.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=directory):
            pass
    except OSError as exc:
        raise OutputError(f"{option} {str(path)!r} cannot be written: {exc.strerror or exc}") from None


def writable_dir(path: str | Path, option: str = "--out") -> Path:
    """``path`` as a directory that exists and can be written now (created if missing)."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputError(f"{option} {str(path)!r} is a file; give a directory (new or existing)")
    _prepare(p, option, path)
    return p


def writable_file(path: str | Path, option: str) -> Path:
    """``path`` as a file that can be written now (its folder created if missing; the file is not)."""
    p = Path(path)
    if p.is_dir():
        raise OutputError(f"{option} {str(path)!r} is a directory; give a file name")
    _prepare(p.parent, option, path)
    return p
