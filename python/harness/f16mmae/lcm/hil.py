"""HIL-style flights: the truth model here, the MMAE executive (``mmae-daemon``) over LCM.

The executive sits beside the flight control computer the way the design card draws it.
Per frame i (docs/INTERFACES.md), over LCM::

    harness                                         mmae-daemon
    z_i = truth.measure()
    publish F16_SENSORS {frame i, z_i}      ->      update(z_i): probabilities, z_hat_i
    wait MMAE_STATUS {frame i}              <-      publish status i
    u_i = fcs.command(z_hat_i | z_i, t_i)
    publish F16_COMMANDS {frame i, u_i}     ->      propagate(u_i)
    truth.advance(u_i)

The loop itself is :func:`f16mmae.closedloop.fly`; this module supplies the estimator it
calls, :class:`RemoteEstimator`, which speaks to the executive instead of holding a bank.
``lockstep`` waits for every status (as fast as possible: the same scenario and seed give
the in-process run's probabilities, to 1e-12); paced mode publishes frame i at wall time
t0 + i / rate and waits at most until the next frame is due: a status that misses that
deadline is counted and the FCS flies on the last z_hat it got.

Run markers (F16_RUN_MARKER: run_start with the scenario, failure at each injection time,
run_end) go into recorded logs for the record; the executive never subscribes to them.
Channel names are UPPER_SNAKE with an optional prefix (:func:`channels`).
"""
from __future__ import annotations

import importlib.util
import json
import os
import shutil
import signal
import subprocess
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .names import FRAME_RATE_HZ, NZ

#: LCM's default URL (what LCM tools use when $LCM_DEFAULT_URL is unset).
DEFAULT_LCM_URL = "udpm://239.255.76.67:7667?ttl=0"


class HilError(RuntimeError):
    """The executive cannot be reached, started, or answered wrongly: the message says why."""


@dataclass(frozen=True)
class Channels:
    sensors: str
    commands: str
    status: str
    reset: str
    run_marker: str


def channels(prefix: str = "") -> Channels:
    """The channel names with ``prefix`` prepended (the daemon's ``--channel-prefix``)."""
    return Channels(prefix + "F16_SENSORS", prefix + "F16_COMMANDS", prefix + "MMAE_STATUS",
                    prefix + "MMAE_RESET", prefix + "F16_RUN_MARKER")


def default_lcm_url() -> str:
    return os.environ.get("LCM_DEFAULT_URL") or DEFAULT_LCM_URL


def frame_utime(i: int, rate_hz: float = FRAME_RATE_HZ) -> int:
    """Simulation time of frame i in microseconds (exact for 64 Hz: 15625 us per frame)."""
    return int(round(i * 1e6 / rate_hz))


# -- the executables ----------------------------------------------------------------------------
def sensor_frame_bytes(i: int, z, valid: bool = True, rate_hz: float = FRAME_RATE_HZ) -> bytes:
    """Frame ``i``'s measurements ``z`` (absolute, names.SENSORS order) as an encoded
    ``lcmt_sensor_frame`` (utime = i / rate_hz); ``valid`` flags every sensor."""
    from .lcmt_sensor_frame import lcmt_sensor_frame

    msg = lcmt_sensor_frame()
    msg.utime, msg.frame = frame_utime(i, rate_hz), i
    msg.z = [float(v) for v in z]
    msg.valid = [bool(valid)] * len(msg.z)
    return msg.encode()


def command_frame_bytes(i: int, u, rate_hz: float = FRAME_RATE_HZ) -> bytes:
    """Frame ``i``'s surface commands ``u`` (rad, names.ACTUATORS order) as an encoded
    ``lcmt_command_frame``."""
    from .lcmt_command_frame import lcmt_command_frame

    msg = lcmt_command_frame()
    msg.utime, msg.frame = frame_utime(i, rate_hz), i
    msg.u_rad = [float(v) for v in u]
    return msg.encode()


def find_executable(name: str = "mmae-daemon") -> Path:
    """``mmae-daemon`` or ``lcm-echo-f16``: $F16MMAE_BIN_DIR, then the package's ``bin``
    folder (where ``pip install .`` / ``make build`` put them, beside the compiled core),
    then $PATH. Raises HilError naming the places looked at."""
    places: list[Path] = []
    env = os.environ.get("F16MMAE_BIN_DIR")
    if env:
        places.append(Path(env) / name)
    for module in ("f16mmae.core", "f16mmae.lcmt_mmae_status"):
        spec = importlib.util.find_spec(module)
        if spec is not None and spec.origin:
            places.append(Path(spec.origin).parent / "bin" / name)
    places.append(Path(__file__).resolve().parent / "bin" / name)
    for p in places:
        if p.is_file() and os.access(p, os.X_OK):
            return p
    on_path = shutil.which(name)
    if on_path:
        return Path(on_path)
    raise HilError(f"cannot find {name}: looked in {', '.join(str(p.parent) for p in places)} and $PATH; "
                   f"build it with 'make build' (or set F16MMAE_BIN_DIR)")


def pin_to(cpus: set[int] | None):
    """A ``preexec_fn`` that runs a child process (and every thread it starts) on ``cpus``;
    None when ``cpus`` is None (no pinning)."""
    if cpus is None:
        return None
    cpus = set(cpus)
    return lambda: os.sched_setaffinity(0, cpus)


class DaemonProcess:
    """A ``mmae-daemon`` child process: started and ready (its ready line read), stopped
    with SIGINT, its one-line statistics summary kept in :attr:`summary`."""

    def __init__(self, bank_path: str | Path, *, lcm_url: str, channel_prefix: str = "",
                 extra_args: tuple[str, ...] = (), ready_timeout_s: float = 10.0,
                 cpus: set[int] | None = None) -> None:
        exe = find_executable("mmae-daemon")
        self.args = [str(exe), "--bank", str(bank_path), "--lcm-url", lcm_url,
                     "--channel-prefix", channel_prefix, *extra_args]
        self.summary = ""
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
        if "ready" not in line:
            self.stop()
            err = self._stderr.strip() if hasattr(self, "_stderr") else ""
            raise HilError(f"mmae-daemon did not start ({' '.join(self.args)}): "
                           f"{err or line or f'no ready line within {timeout_s:g} s'}")
        return line

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
        lines = [ln for ln in (out or "").splitlines() if ln.startswith("mmae-daemon:")]
        self.summary = lines[-1] if lines else ""
        self.returncode = self._proc.returncode
        return self.returncode

    def __enter__(self) -> "DaemonProcess":
        return self

    def __exit__(self, *exc) -> None:
        self.stop()


# -- the estimator the closed loop calls ----------------------------------------------------------
@dataclass
class LinkStats:
    """What the link did during one flight."""
    frames: int = 0
    latency_ns: list[int] = field(default_factory=list)   # sensor publish -> status received
    deadline_misses: int = 0                               # paced: no status before the next frame
    stale_statuses: int = 0                                # statuses the executive marked stale

    def summary(self) -> dict:
        lat = np.array(self.latency_ns, dtype=float) / 1e3
        q = (lambda p: round(float(np.percentile(lat, p)), 1)) if lat.size else (lambda p: None)
        return {"frames": self.frames, "statuses": int(lat.size), "deadline_misses": self.deadline_misses,
                "stale_statuses": self.stale_statuses,
                "latency_us": {"p50": q(50), "p99": q(99), "max": round(float(lat.max()), 1) if lat.size else None}}


class RemoteEstimator:
    """The MMAE executive over LCM, with the interface :func:`closedloop.fly` calls
    (``update(z) -> z_hat``, ``propagate(u)``, ``hypotheses``, ``probabilities``,
    ``declared``, ``bank_hash``). Only u and z cross the link.

    ``lockstep``: each update waits for its status up to ``timeout_s`` (HilError after).
    Paced: frame i is published at ``t0 + i / rate_hz`` and its status awaited until the next
    frame is due; a miss leaves z_hat and the probabilities at their last values (before the
    first status, z_hat is the raw z: what an FCS falls back to without its estimator)."""

    def __init__(self, lc, chans: Channels, *, lockstep: bool = True, rate_hz: float = FRAME_RATE_HZ,
                 timeout_s: float = 5.0, expected_bank_hash: str | None = None,
                 initial_hypotheses: tuple[str, ...] = ()) -> None:
        from .lcmt_mmae_status import lcmt_mmae_status

        self._lc, self._ch = lc, chans
        self.lockstep, self.rate_hz, self.timeout_s = lockstep, rate_hz, timeout_s
        self.expected_bank_hash = expected_bank_hash
        self._initial_hypotheses = tuple(initial_hypotheses)
        #: The hypothesis declared by the last update's status (a back-out declares NONE), or None.
        self.last_declaration: str | None = None
        self._decode = lcmt_mmae_status.decode
        self._frame = -1
        self._t_pub = 0
        self._t0: float | None = None
        self._status = None
        self._z_hat = np.full(NZ, np.nan)
        self.link = LinkStats()
        #: The estimator settings the executive is presumed to run (the record's estimator_settings).
        self.settings: dict = {}
        self._sub = lc.subscribe(chans.status, self._on_status)

    def close(self) -> None:
        if self._sub is not None:
            self._lc.unsubscribe(self._sub)
            self._sub = None

    # -- LCM side
    def _on_status(self, channel, data) -> None:
        t = time.perf_counter_ns()
        msg = self._decode(data)
        if msg.frame != self._frame or (self._status is not None and self._status.frame == self._frame):
            return  # an old frame's status (or a repeat): not ours to use
        self.link.latency_ns.append(t - self._t_pub)
        if msg.stale:
            self.link.stale_statuses += 1
        self._status = msg

    def frame_due(self, i: float) -> float | None:
        """Paced mode: the perf_counter time at which frame i (may be fractional) is due."""
        return None if self._t0 is None else self._t0 + i / self.rate_hz

    def reset(self, reason: str = "") -> None:
        """A new flight on the executive (MMAE_RESET); frame counting restarts at 0."""
        from .lcmt_mmae_reset import lcmt_mmae_reset

        msg = lcmt_mmae_reset()
        msg.utime = 0
        msg.reason = reason
        self._lc.publish(self._ch.reset, msg.encode())
        self._frame = -1
        self._status = None
        self._t0 = None

    # -- the estimator interface
    def update(self, z) -> np.ndarray:
        z = np.array(z, dtype=float).reshape(-1)
        self._frame += 1
        i = self._frame
        data = sensor_frame_bytes(i, z, rate_hz=self.rate_hz)
        if not self.lockstep:
            if self._t0 is None:
                self._t0 = time.perf_counter()
            due = self._t0 + i / self.rate_hz
            while (wait := due - time.perf_counter()) > 0:
                time.sleep(wait)
            deadline = due + 1.0 / self.rate_hz
        else:
            deadline = time.perf_counter() + self.timeout_s
        self._t_pub = time.perf_counter_ns()
        self._lc.publish(self._ch.sensors, data)
        self.link.frames += 1
        self.last_declaration = None
        while self._status is None or self._status.frame != i:
            left = deadline - time.perf_counter()
            if left <= 0:
                break
            self._lc.handle_timeout(max(1, int(left * 1000)))
        if self._status is None or self._status.frame != i:
            if self.lockstep:
                raise HilError(f"no MMAE_STATUS for frame {i} within {self.timeout_s:g} s on "
                               f"{self._ch.status!r}: is mmae-daemon running on this LCM URL with the "
                               f"same --channel-prefix?")
            self.link.deadline_misses += 1
            return self._z_hat.copy() if np.all(np.isfinite(self._z_hat)) else z.copy()
        if self.expected_bank_hash and self._status.bank_hash != self.expected_bank_hash:
            raise HilError(f"the executive runs bank {self._status.bank_hash[:12]}, this flight was set up "
                           f"for bank {self.expected_bank_hash[:12]}: start mmae-daemon with the same --bank")
        self._z_hat = np.array(self._status.z_hat, dtype=float)
        self.last_declaration = self._status.declaration or None
        return self._z_hat.copy()

    def propagate(self, u) -> None:
        u = np.array(u, dtype=float).reshape(-1)
        self._lc.publish(self._ch.commands, command_frame_bytes(self._frame, u, self.rate_hz))

    @property
    def hypotheses(self) -> tuple[str, ...]:
        """Names on line (from the last status; before it, the bank's level 0)."""
        return tuple(self._status.hypothesis_names) if self._status is not None else self._initial_hypotheses

    @property
    def probabilities(self) -> np.ndarray:
        if self._status is None:
            return np.zeros(0)
        return np.array(self._status.probabilities, dtype=float)

    @property
    def declared(self) -> str:
        return self._status.declared if self._status is not None else "NONE"

    @property
    def level(self) -> int:
        return int(self._status.bank_level) if self._status is not None else 0

    @property
    def bank_hash(self) -> str:
        return self._status.bank_hash if self._status is not None else (self.expected_bank_hash or "")


def level0_hypotheses(model_bank) -> tuple[str, ...]:
    """NONE and the single failures, in the bank's order (the executive's level 0)."""
    names = [h.name for h in model_bank.hypotheses]
    return tuple(n for n in names if "+" not in n)


# -- run markers ------------------------------------------------------------------------------------
def publish_marker(lc, chans: Channels, event: str, time_s: float, payload: dict) -> None:
    from .lcmt_run_marker import lcmt_run_marker

    msg = lcmt_run_marker()
    msg.utime = int(round(time_s * 1e6))
    msg.event = event
    msg.payload_json = json.dumps(payload, sort_keys=True)
    lc.publish(chans.run_marker, msg.encode())


def fly_hil(scenario, model_bank, lc, chans: Channels, *, lockstep: bool = True,
            timeout_s: float = 5.0, feedback: str | None = None, on_frame=None,
            remote: RemoteEstimator | None = None):
    """Fly ``scenario`` against the executive reachable on ``lc``; returns the closed loop's
    FlightResult (timing gains ``link``: latency p50/p99/max, deadline misses, stale).
    ``on_frame(t, u, z)`` is called after each frame, as by closedloop.fly; ``remote``: a
    RemoteEstimator of the caller's (then ``lockstep``/``timeout_s`` are its own)."""
    from . import closedloop

    if remote is None:
        remote = RemoteEstimator(lc, chans, lockstep=lockstep, timeout_s=timeout_s,
                                 expected_bank_hash=str(model_bank.content_hash),
                                 initial_hypotheses=level0_hypotheses(model_bank))
    lockstep = remote.lockstep
    # what mmae-daemon applies by default: the bank's recommended settings (cpp/daemon/bank_settings.h)
    remote.settings = closedloop.bank_estimator_settings(model_bank)
    try:
        remote.reset(f"f16mmae hil: seed {scenario.seed}")
        publish_marker(lc, chans, "run_start", 0.0, {
            "scenario": scenario.to_dict(), "bank_hash": str(model_bank.content_hash),
            "lockstep": lockstep})
        pending = sorted((f.time_s, f.to_dict()) for f in scenario.failures)

        def frame_done(t, u, z):
            while pending and pending[0][0] <= t:
                publish_marker(lc, chans, "failure", t, pending.pop(0)[1])
            if on_frame is not None:
                on_frame(t, u, z)

        result = closedloop.fly(scenario, model_bank, feedback=feedback, on_frame=frame_done, estimator=remote)
        link = remote.link.summary()
        publish_marker(lc, chans, "run_end", scenario.duration_s, {
            "frames": link["frames"], "declarations": result.declarations,
            "final_hypothesis": result.final_hypothesis})
        result.timing["link"] = link
        result.timing["mode"] = "lockstep" if lockstep else "paced"
        return result
    finally:
        remote.close()
