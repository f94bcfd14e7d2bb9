"""The results store: one JSON-lines record per finished run, appended as runs finish.

File: ``DIR/runs.jsonl``, one JSON object per line, written by the campaign's parent
process only (workers return records; the parent appends them). Each line is flushed to the
operating system as it is written, so a campaign killed at any moment loses at most the run
being written; the file is fsync'ed at most once per ``sync_interval_s`` (1 s) and when the
store is closed, so a crash of the machine itself loses at most the last second's runs. (An
fsync per line cost as much as the flights of a short campaign.) A resume flies the lost
runs again.

Resume: every record carries ``run_key``, the SHA-256 of the canonical JSON of what
determines the run's result (scenario incl. seed, bank hash, code version, estimator
settings; see :func:`run_key`).  A campaign started again with the same arguments plans
the same keys and skips those already stored.  A half-written last line (a kill during a
write) is recognised on opening -- the file does not end in a newline -- and cut back to
the last complete record; that run is simply run again.  A malformed line anywhere else
is corruption and is refused with its line number.
"""
from __future__ import annotations

import contextlib
import errno
import fcntl
import hashlib
import json
import os
import time
from pathlib import Path
from typing import Any, Iterable, Iterator

from ...errors import F16mmaeError
from ...outputs import writable_dir

RECORDS_FILE = "runs.jsonl"
#: The lock a campaign holds on its directory while it runs (the holder's pid inside).
LOCK_FILE = ".campaign.lock"


class StoreError(F16mmaeError):
    """The results file cannot be read as a sequence of records."""


SUMMARY_FILE = "summary.json"


def write_summary(path: str | os.PathLike, summary: dict) -> Path:
    """Write a campaign's summary as one compact JSON document (C-encoded: an indented dump
    of an envelope campaign's summary cost a fifth of a second, and it is written twice)."""
    p = Path(path)
    p.write_text(json.dumps(summary, separators=(",", ":")) + "\n")
    return p


def canonical_json(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"))


def run_key(identity: dict) -> str:
    """Key of a run from everything that determines its result (a JSON-able dict)."""
    return hashlib.sha256(canonical_json(identity).encode()).hexdigest()[:32]


class ResultsStore:
    """Append-only JSON-lines records under ``directory / RECORDS_FILE``."""

    def __init__(self, directory: str | os.PathLike, sync_interval_s: float = 1.0) -> None:
        self.directory = Path(directory)
        self.path = self.directory / RECORDS_FILE
        self.repaired_bytes = 0  # bytes of a half-written last line cut on opening
        self.sync_interval_s = sync_interval_s
        self._file = None  # the append handle, open from the first append until close()
        self._synced_at = 0.0

    def __enter__(self) -> "ResultsStore":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- reading ---------------------------------------------------------------------
    def _repair_tail(self) -> None:
        """Cut a half-written last line so appends start on a fresh line."""
        if not self.path.exists():
            return
        size = self.path.stat().st_size
        if size == 0:
            return
        with open(self.path, "rb+") as f:
            f.seek(size - 1)
            if f.read(1) == b"\n":
                return
            # Find the last newline; everything after it is an unfinished record.
            block = 1 << 16
            pos = size
            keep = 0
            while pos > 0:
                start = max(0, pos - block)
                f.seek(start)
                chunk = f.read(pos - start)
                nl = chunk.rfind(b"\n")
                if nl >= 0:
                    keep = start + nl + 1
                    break
                pos = start
            f.truncate(keep)
            self.repaired_bytes = size - keep

    def records(self) -> list[dict]:
        """Every complete record, in the order written."""
        return list(self._iter_records())

    def _iter_records(self) -> Iterator[dict]:
        self._repair_tail()
        if not self.path.exists():
            return
        with open(self.path, encoding="utf-8") as f:
            for lineno, line in enumerate(f, 1):
                if not line.strip():
                    continue
                try:
                    record = json.loads(line)
                except json.JSONDecodeError as exc:
                    raise StoreError(
                        f"{self.path}:{lineno}: not a JSON record ({exc.msg}); the results "
                        f"file is corrupt -- move it away or pass a new --out directory"
                    ) from None
                if not isinstance(record, dict) or "run_key" not in record:
                    raise StoreError(f"{self.path}:{lineno}: record without a run_key")
                yield record

    def keys(self) -> set[str]:
        return {r["run_key"] for r in self._iter_records()}

    # -- writing ---------------------------------------------------------------------
    def append(self, record: dict) -> None:
        """Append one record as one line: flushed at once, fsync'ed as the module says."""
        if "run_key" not in record:
            raise ValueError("a stored record needs a run_key")
        line = json.dumps(record, separators=(",", ":"), allow_nan=False) + "\n"
        if self._file is None:
            self.directory.mkdir(parents=True, exist_ok=True)
            self._repair_tail()
            self._file = open(self.path, "a", encoding="utf-8")
            self._synced_at = time.monotonic()
        self._file.write(line)
        self._file.flush()
        if time.monotonic() - self._synced_at >= self.sync_interval_s:
            self.sync()

    def sync(self) -> None:
        """fsync what has been appended."""
        if self._file is not None:
            os.fsync(self._file.fileno())
            self._synced_at = time.monotonic()

    def close(self) -> None:
        """fsync and close the append handle (a later append opens it again)."""
        if self._file is not None:
            try:
                self.sync()
            finally:
                self._file.close()
                self._file = None

    def extend(self, records: Iterable[dict]) -> None:
        for r in records:
            self.append(r)


@contextlib.contextmanager
def campaign_directory(directory: str | os.PathLike) -> Iterator[Path]:
    """The campaign's output directory, checked writable (``outputs.writable_dir``, before
    any flight) and locked for this process until the block ends; StoreError naming the
    directory and the holder's pid when another campaign has it."""
    d = writable_dir(directory, "--out")
    f = open(d / LOCK_FILE, "a+", encoding="utf-8")
    try:
        try:
            fcntl.lockf(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            if exc.errno not in (errno.EACCES, errno.EAGAIN):
                raise StoreError(f"cannot lock {d / LOCK_FILE}: {exc.strerror}") from None
            f.seek(0)
            holder = f.read().strip() or "unknown"
            raise StoreError(f"another campaign (pid {holder}) is writing to {d}; wait until it ends, "
                             f"or give another --out directory") from None
        f.seek(0)
        f.truncate()
        f.write(f"{os.getpid()}\n")
        f.flush()
        yield d
    finally:
        f.close()  # closing the only descriptor of the file drops the lock
