"""A dependency-free progress bar on stderr: runs done, rate and time left.

    rate_per_s = done / elapsed_s          (runs finished since the bar started)
    left_s     = (total - done) / rate_per_s

On a terminal the bar redraws one line in place (``\\r``); on a pipe or a log file it
prints a plain line at most every ``log_interval_s`` seconds and at the end, so CI logs
stay short.  ``done`` may start above zero (runs resumed from a results store): those
count towards the bar but not towards the rate.
"""
from __future__ import annotations

import sys
import time
from typing import TextIO


def _clock(seconds: float) -> str:
    seconds = max(0, int(round(seconds)))
    minutes, s = divmod(seconds, 60)
    hours, m = divmod(minutes, 60)
    return f"{hours:d}:{m:02d}:{s:02d}" if hours else f"{m:02d}:{s:02d}"


class Progress:
    """``Progress(total, label)``; call ``advance()`` once per finished run, ``close()`` at the end."""

    def __init__(
        self,
        total: int,
        label: str = "runs",
        *,
        already_done: int = 0,
        stream: TextIO | None = None,
        width: int = 28,
        log_interval_s: float = 5.0,
        enabled: bool = True,
    ) -> None:
        if total < 0 or already_done < 0 or already_done > total:
            raise ValueError(f"progress needs 0 <= already_done <= total, got {already_done}/{total}")
        self.total = total
        self.label = label
        self.done = already_done
        self._resumed = already_done
        self._stream = stream if stream is not None else sys.stderr
        self._tty = bool(getattr(self._stream, "isatty", lambda: False)())
        self._width = width
        self._log_interval_s = log_interval_s
        self._enabled = enabled
        self._t0 = time.perf_counter()
        self._last_print = -float("inf")
        self._closed = False
        self._draw(force=True)

    @property
    def rate_per_s(self) -> float:
        elapsed = time.perf_counter() - self._t0
        new = self.done - self._resumed
        return new / elapsed if elapsed > 0 and new > 0 else 0.0

    def line(self) -> str:
        """The text of the bar as it would be drawn now."""
        frac = self.done / self.total if self.total else 1.0
        filled = int(round(frac * self._width))
        bar = "#" * filled + "-" * (self._width - filled)
        rate = self.rate_per_s
        elapsed = time.perf_counter() - self._t0
        if self.done >= self.total:
            tail = f"{_clock(elapsed)} elapsed"
        elif rate > 0:
            tail = f"{_clock((self.total - self.done) / rate)} left"
        else:
            tail = "--:-- left"
        resumed = f" ({self._resumed} resumed)" if self._resumed else ""
        return (
            f"{self.label} [{bar}] {self.done}/{self.total}{resumed} "
            f"{rate:.1f}/s {tail}"
        )

    def advance(self, n: int = 1) -> None:
        self.done = min(self.total, self.done + n)
        self._draw(force=self.done >= self.total)

    def _draw(self, force: bool = False) -> None:
        if not self._enabled or self._closed:
            return
        now = time.perf_counter()
        if self._tty:
            if force or now - self._last_print >= 0.1:
                self._stream.write("\r" + self.line() + "\x1b[K")
                self._stream.flush()
                self._last_print = now
        elif force or now - self._last_print >= self._log_interval_s:
            self._stream.write(self.line() + "\n")
            self._stream.flush()
            self._last_print = now

    def close(self) -> None:
        if self._closed:
            return
        if self._enabled:
            if self._tty:
                self._stream.write("\r" + self.line() + "\x1b[K\n")
            elif self.done < self.total:
                self._stream.write(self.line() + "\n")
            self._stream.flush()
        self._closed = True

    def __enter__(self) -> "Progress":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
