"""The ``mmae-daemon`` executable: find it, start it as a child process, stop it."""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sysconfig
import threading
from pathlib import Path

from ..loop.estimator import core_arguments
from ..loop.estimator_options import BY_KEY, CLOSED_LOOP
from ..names import SINGLE_HYPOTHESES
from .channels import HilError


def statistics_line(output: str, program: str) -> dict:
    """The statistics a program of ours printed as ``PROGRAM: statistics {JSON}`` (the last
    such line of ``output``), as a dict; HilError when there is none or it is not JSON."""
    head = f"{program}: statistics "
    lines = [ln[len(head):] for ln in (output or "").splitlines() if ln.startswith(head)]
    if not lines:
        raise HilError(f"{program} printed no statistics line ({head.strip()!r}); its output was: "
                       f"{(output or '').strip()[-500:]!r}")
    try:
        return json.loads(lines[-1])
    except ValueError as exc:
        raise HilError(f"{program}'s statistics line is not JSON ({exc}): {lines[-1][:200]!r}") from None


#: The core keywords ``core_arguments`` renames (the per-hypothesis tempering's, the calm-air bounds) and
#: the rows whose flags give them.
_RENAMED_KEYS = {"adapt_hypothesis_weight": "set_tempering", "adapt_spare_rho": "set_tempering_rho",
                 "adapt_rough_rho": "set_tempering_rough", "adapt_rough_weight": "set_tempering_rough_weight",
                 "adapt_spare_margin": "set_tempering_margin", "calm_complete_rho": "calm_complete"}
#: The core's bit masks over z and the rows whose flags take the sensor's name.
_CHANNEL_BITS_KEYS = {"adapt_counted_channels": "adapt_counted_channel",
                      "adapt_excluded_channels": "adapt_excluded_channel",
                      "adapt_level_scale_channels": "adapt_level_scale_channel"}
#: The steady trim tracking's air-data limits, infinite from ``trim_steady_air_data`` "off"
#: (``loop.estimator.core_arguments``); the daemon takes ``--trim-tracking-steady-air-data off``.
_STEADY_AIR_DATA_KEYS = ("trim_steady_climb_ft_s", "trim_steady_mach_per_s")
#: The core's bit masks over the level-0 hypotheses and the ``mmae-daemon`` flags that take their names.
_HYPOTHESIS_BITS_FLAGS = {"adapt_full_tempering": "--set-tempering-full",
                          "adapt_spare_margin_over": "--set-tempering-margin-over",
                          "adapt_rough_tempering": "--set-tempering-rough-full"}


def daemon_flags(estimator_options: dict, nu: int = 5) -> tuple[str, ...]:
    """The ``mmae-daemon`` arguments that give it ``estimator_options`` for a bank of ``nu``
    inputs (``actuator_limits`` becomes the limits themselves, as in process:
    ``loop.estimator.core_arguments``; the closed loop's options, ``CLOSED_LOOP``, need none: the
    adaptive dither reads the status; ValueError for an option the daemon has no flag for)."""
    out: list[str] = []
    for key, value in core_arguments(estimator_options, nu).items():
        if key in CLOSED_LOOP:   # the closed loop's (the truth side's): the executive needs no flag
            continue
        if key in _STEADY_AIR_DATA_KEYS:   # core_arguments' infinite limits: the daemon takes on|off
            if key == _STEADY_AIR_DATA_KEYS[0]:
                out += ["--trim-tracking-steady-air-data", "off"]
            continue
        if key in _CHANNEL_BITS_KEYS:   # core_arguments' bit; the daemon takes the sensor's name
            key = _CHANNEL_BITS_KEYS[key]
            value = estimator_options[key]
        if key in _HYPOTHESIS_BITS_FLAGS:   # core_arguments' bits; the daemon takes the hypotheses' names
            out += [_HYPOTHESIS_BITS_FLAGS[key], ",".join(h for k, h in enumerate(SINGLE_HYPOTHESES) if (value >> k) & 1)]
            continue
        key = _RENAMED_KEYS.get(key, key)
        option = BY_KEY.get(key)
        if option is None or not option.in_daemon:
            if option is not None and not value:
                continue
            raise ValueError(f"mmae-daemon has no flag for the estimator option {key!r}; "
                             f"it takes {', '.join(k for k, o in BY_KEY.items() if o.in_daemon)}")
        if option.kind == "switch":
            out += [option.flag] if value else []
        elif option.kind == "values":
            out += [option.flag, ",".join(repr(float(v)) for v in value)]
        elif option.kind in ("file", "table"):   # the path or text as given (core_arguments has read its table)
            given = estimator_options[key]
            out += [option.flag, ",".join(given) if isinstance(given, (list, tuple)) else str(given)]
        else:
            out += [option.flag, value if option.kind == "choice" else repr(float(value))]
    return tuple(out)


def find_executable(name: str = "mmae-daemon") -> Path:
    """``mmae-daemon``: $F16MMAE_BIN_DIR, then the scripts directory of this Python (where
    ``pip install .`` and ``make build`` put it, beside ``f16mmae``), then $PATH. Raises
    HilError naming the places looked at."""
    places: list[Path] = []
    env = os.environ.get("F16MMAE_BIN_DIR")
    if env:
        places.append(Path(env) / name)
    places.append(Path(sysconfig.get_path("scripts")) / name)
    for p in places:
        if p.is_file() and os.access(p, os.X_OK):
            return p
    on_path = shutil.which(name)
    if on_path:
        return Path(on_path)
    raise HilError(f"cannot find {name}: looked in {', '.join(str(p.parent) for p in places)} and $PATH; "
                   f"install the package ('pip install .' or 'make build'), or set F16MMAE_BIN_DIR")


def pin_to(cpus: set[int] | None):
    """A ``preexec_fn`` that runs a child process (and every thread it starts) on ``cpus``;
    None when ``cpus`` is None (no pinning)."""
    if cpus is None:
        return None
    cpus = set(cpus)
    return lambda: os.sched_setaffinity(0, cpus)


class DaemonProcess:
    """A ``mmae-daemon`` child process: started and ready (its ready line read), stopped
    with SIGINT; its human summary line kept in :attr:`summary`, its statistics line parsed
    into :attr:`statistics` (LcmNode::statistics_json: messages by fate, frame counters,
    step times)."""

    def __init__(self, bank_path: str | Path, *, lcm_url: str, channel_prefix: str = "",
                 extra_args: tuple[str, ...] = (), ready_timeout_s: float = 10.0,
                 cpus: set[int] | None = None, auth_key: str | Path | None = None) -> None:
        exe = find_executable("mmae-daemon")
        key = ("--auth-key", str(auth_key)) if auth_key is not None else ()
        self.args = [str(exe), "--bank", str(bank_path), "--lcm-url", lcm_url,
                     "--channel-prefix", channel_prefix, *key, *extra_args]
        self.summary = ""
        self.ready_line_seen = False
        self.statistics: dict = {}
        self.returncode: int | None = None
        self._proc = subprocess.Popen(self.args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                      text=True, bufsize=1, preexec_fn=pin_to(cpus))
        self.ready_line = self._read_ready(ready_timeout_s)

    def _read_ready(self, timeout_s: float) -> str:
        box: list[str] = []
        reader = threading.Thread(target=lambda: box.append(self._proc.stdout.readline()), daemon=True)
        reader.start()
        reader.join(timeout_s)
        line = box[0].strip() if box else ""
        self.ready_line_seen = "ready" in line
        if "ready" not in line:
            self.stop()
            err = self._stderr.strip() if hasattr(self, "_stderr") else ""
            raise HilError(f"mmae-daemon did not start ({' '.join(self.args)}): "
                           f"{err or line or f'no ready line within {timeout_s:g} s'}")
        return line

    @property
    def pid(self) -> int:
        return self._proc.pid

    def stop(self, timeout_s: float = 5.0) -> int:
        """SIGINT, wait, keep the summary line; returns the exit status."""
        if self.returncode is not None:
            return self.returncode
        if self._proc.poll() is None:
            self._proc.send_signal(signal.SIGINT)
        try:
            out, err = self._proc.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            out, err = self._proc.communicate()
        self._stderr = err or ""
        lines = [ln for ln in (out or "").splitlines()
                 if ln.startswith("mmae-daemon:") and not ln.startswith("mmae-daemon: statistics ")]
        self.summary = lines[-1] if lines else ""
        self.returncode = self._proc.returncode
        if self.ready_line_seen and self.returncode == 0:  # a clean end always prints it
            self.statistics = statistics_line(out, "mmae-daemon")
        return self.returncode

    def __enter__(self) -> "DaemonProcess":
        return self

    def __exit__(self, *exc) -> None:
        self.stop()
