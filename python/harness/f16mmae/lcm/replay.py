"""Replay recorded executive traffic through the in-process bank and compare, frame by frame.

A log written by the stock ``lcm-logger`` (or any LCM event log) holds the sensor frames,
command frames and status frames of a flight. :func:`replay_log` feeds the sensor and
command frames, in log order, through :class:`InProcessExecutive` -- the same frame rules as
``mmae-daemon`` (cpp/daemon/frame_sequencer.h: duplicates and late frames dropped, lost
frames propagated with the held command without update, non-finite or invalid frames
rejected) around the in-process estimator of :mod:`f16mmae.loop.estimator` -- and compares each
logged status with the one computed here for the same frame: hypothesis names, bank level,
declaration, stale flag, and the largest absolute difference of the probabilities and of
z_hat. A reset on MMAE_RESET starts a new flight, as on the daemon.

:class:`InProcessExecutive` can also answer over LCM (:meth:`InProcessExecutive.serve`), so
the harness's LCM path is testable in one process over ``memq://``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import lcm
import numpy as np

from ..errors import F16mmaeError
from ..lcmt_command_frame import lcmt_command_frame
from ..lcmt_mmae_status import lcmt_mmae_status
from ..lcmt_sensor_frame import lcmt_sensor_frame
from ..loop.estimator import Estimator
from .channels import Channels, channels


class ReplayError(F16mmaeError, RuntimeError):
    """The log cannot be read or does not hold executive traffic."""


class FrameSequencer:
    """The daemon's frame rules (cpp/daemon/frame_sequencer.h), in Python for replay.
    ``on_sensor(n)`` / ``on_command(n)`` return ``(accept, catch_up)``."""

    def __init__(self) -> None:
        self.counters = dict(frames_updated=0, frames_rejected=0, dropped_duplicate=0,
                             dropped_out_of_order=0, frames_stale=0, commands_missed=0)
        self.reset()

    def reset(self) -> None:
        self.started = False
        self.p = 0
        self.p_updated = False
        self.last_sensor = self.last_command = None
        self.stale_since_status = 0

    def _drop(self, duplicate: bool):
        self.counters["dropped_duplicate" if duplicate else "dropped_out_of_order"] += 1
        return False, 0

    def _catch_up(self, k: int) -> None:
        if k <= 0:
            return
        self.counters["commands_missed"] += k
        stale = k - (1 if self.p_updated else 0)
        self.counters["frames_stale"] += stale
        self.stale_since_status += stale
        self.p_updated = False

    def on_sensor(self, n: int):
        if not self.started:
            self.started, self.p, self.p_updated = True, n, False
        if n < self.p or (n == self.p and self.p_updated):
            return self._drop(n == self.last_sensor)
        k = n - self.p
        self._catch_up(k)
        self.p, self.p_updated, self.last_sensor = n, True, n
        self.counters["frames_updated"] += 1
        return True, k

    def on_command(self, n: int):
        if not self.started or n < self.p:
            return self._drop(self.started and n == self.last_command)
        k = n - self.p
        self._catch_up(k)
        if not (k == 0 and self.p_updated):
            self.counters["frames_stale"] += 1
            self.stale_since_status += 1
        self.p, self.p_updated, self.last_command = n + 1, False, n
        return True, k

    def on_rejected(self) -> None:
        self.counters["frames_rejected"] += 1

    def take_stale_since_status(self) -> int:
        s, self.stale_since_status = self.stale_since_status, 0
        return s


@dataclass
class ComputedStatus:
    frame: int
    hypotheses: tuple[str, ...]
    probabilities: np.ndarray
    z_hat: np.ndarray
    level: int
    declared: str
    declaration: str          # declared by this frame's update, "" if none
    stale: bool
    frames_without_update: int


class InProcessExecutive:
    """The executive's frame handling around the in-process estimator (absolute u, z)."""

    def __init__(self, model_bank, **estimator_options) -> None:
        self._make = lambda: Estimator(model_bank, **estimator_options)
        self.estimator = self._make()
        self.bank_hash = str(model_bank.content_hash)
        self.u_trim = np.array(model_bank.u_trim, dtype=float)
        self.sequencer = FrameSequencer()
        self.u_held = self.u_trim.copy()

    def reset(self) -> None:
        self.estimator = self._make()
        self.sequencer.reset()
        self.u_held = self.u_trim.copy()

    def _catch_up(self, k: int) -> None:
        for _ in range(k):
            self.estimator.propagate(self.u_held)

    def on_sensor(self, frame: int, z, valid=None) -> ComputedStatus | None:
        z = np.array(z, dtype=float)
        if not np.all(np.isfinite(z)) or (valid is not None and not all(valid)):
            self.sequencer.on_rejected()
            return None
        accept, k = self.sequencer.on_sensor(int(frame))
        if not accept:
            return None
        self._catch_up(k)
        z_hat = self.estimator.update(z)
        stale = self.sequencer.take_stale_since_status()
        names = self.estimator.hypotheses
        return ComputedStatus(int(frame), tuple(names), np.array(self.estimator.probabilities, dtype=float),
                              np.array(z_hat, dtype=float), int(self.estimator.level), self.estimator.declared,
                              self.estimator.last_declaration or "", stale > 0, stale)

    def on_command(self, frame: int, u) -> bool:
        u = np.array(u, dtype=float)
        if not np.all(np.isfinite(u)):
            self.sequencer.on_rejected()
            return False
        accept, k = self.sequencer.on_command(int(frame))
        if not accept:
            return False
        self._catch_up(k)
        self.u_held = u
        self.estimator.propagate(u)
        return True

    # -- answering over LCM (tests over memq://) ---------------------------------------------------
    def status_message(self, computed: ComputedStatus, utime: int):
        m = lcmt_mmae_status()
        m.utime, m.frame, m.bank_hash = utime, computed.frame, self.bank_hash
        m.bank_level = computed.level
        m.level_failure = computed.hypotheses[1] if computed.level == 1 else ""
        m.declared = computed.declared
        m.declaration = computed.declaration
        m.num_hypotheses = len(computed.hypotheses)
        m.hypothesis_names = list(computed.hypotheses)
        m.probabilities = [float(p) for p in computed.probabilities]
        m.z_hat = [float(v) for v in computed.z_hat]
        m.stale, m.frames_without_update = computed.stale, computed.frames_without_update
        c = self.sequencer.counters
        m.frames_updated, m.frames_rejected = c["frames_updated"], c["frames_rejected"]
        m.frames_dropped = c["dropped_duplicate"] + c["dropped_out_of_order"]
        m.frames_stale, m.commands_missed = c["frames_stale"], c["commands_missed"]
        m.step_time_ns = 0
        return m

    def serve(self, lc, chans: Channels) -> list:
        """Subscribe to the sensor, command and reset channels of ``lc`` and publish statuses,
        as mmae-daemon does. Returns the subscriptions (unsubscribe to stop)."""
        def on_sensor(channel, data):
            f = lcmt_sensor_frame.decode(data)
            computed = self.on_sensor(f.frame, f.z, f.valid)
            if computed is not None:
                lc.publish(chans.status, self.status_message(computed, f.utime).encode())

        def on_command(channel, data):
            f = lcmt_command_frame.decode(data)
            self.on_command(f.frame, f.u_rad)

        return [lc.subscribe(chans.sensors, on_sensor), lc.subscribe(chans.commands, on_command),
                lc.subscribe(chans.reset, lambda channel, data: self.reset())]


@dataclass
class FrameMismatch:
    frame: int
    what: str

    def __str__(self) -> str:
        return f"frame {self.frame}: {self.what}"


@dataclass
class ReplayReport:
    log: str
    events: int = 0
    sensor_frames: int = 0
    command_frames: int = 0
    statuses_logged: int = 0
    statuses_compared: int = 0
    statuses_unmatched: int = 0          # logged statuses with no frame computed here
    max_probability_diff: float = 0.0
    max_z_hat_diff: float = 0.0
    bank_hashes: set = field(default_factory=set)
    mismatches: list[FrameMismatch] = field(default_factory=list)   # the first few
    mismatch_count: int = 0
    tolerance: float = 1e-12

    @property
    def ok(self) -> bool:
        return self.statuses_compared > 0 and self.mismatch_count == 0


def replay_log(path: str | Path, model_bank, *, channel_prefix: str = "", tolerance: float = 1e-12,
               max_mismatches: int = 20, **estimator_options) -> ReplayReport:
    """Feed the logged frames through the in-process bank; compare with the logged statuses."""
    path = Path(path)
    if not path.is_file():
        raise ReplayError(f"log file {str(path)!r} does not exist")
    try:
        log = lcm.EventLog(str(path), "r")
    except (OSError, ValueError, RuntimeError) as exc:
        raise ReplayError(f"cannot open log {str(path)!r} as an LCM event log: {exc}") from None
    chans = channels(channel_prefix)
    report = ReplayReport(log=str(path), tolerance=tolerance)
    executive = InProcessExecutive(model_bank, **estimator_options)
    computed: dict[int, ComputedStatus] = {}
    # Statuses logged before the sensor frame they answer. The logger, the harness and the
    # daemon are separate processes: on a multi-core host the loopback can hand the logger
    # the daemon's status ahead of the harness's sensor frame that caused it.
    early: dict[int, object] = {}

    def mismatch(frame, what):
        report.mismatch_count += 1
        if len(report.mismatches) < max_mismatches:
            report.mismatches.append(FrameMismatch(frame, what))

    def unmatched(statuses: dict) -> None:
        for frame in sorted(statuses):
            report.statuses_unmatched += 1
            mismatch(frame, "a status was logged for a frame the replay did not update")
        statuses.clear()

    try:
        for event in log:
            report.events += 1
            ch = event.channel
            if ch == chans.sensors:
                f = lcmt_sensor_frame.decode(event.data)
                report.sensor_frames += 1
                c = executive.on_sensor(f.frame, f.z, f.valid)
                if c is not None:
                    if c.frame in early:  # its status was logged before the frame itself
                        _compare(report, early.pop(c.frame), c, mismatch)
                    else:
                        computed[c.frame] = c
            elif ch == chans.commands:
                f = lcmt_command_frame.decode(event.data)
                report.command_frames += 1
                executive.on_command(f.frame, f.u_rad)
            elif ch == chans.reset:
                executive.reset()
                computed.clear()
                unmatched(early)
            elif ch == chans.status:
                s = lcmt_mmae_status.decode(event.data)
                report.statuses_logged += 1
                report.bank_hashes.add(s.bank_hash)
                c = computed.pop(s.frame, None)
                if c is None:
                    early[s.frame] = s  # matched when its sensor frame comes, else unmatched
                    continue
                _compare(report, s, c, mismatch)
        unmatched(early)
    except ValueError as exc:
        raise ReplayError(f"log {str(path)!r}: a frame does not decode ({exc}); "
                          f"is it f16mmae traffic of this version?") from None
    finally:
        log.close()
    if report.statuses_logged == 0:
        raise ReplayError(f"log {str(path)!r} holds no {chans.status!r} messages "
                          f"(channel prefix {channel_prefix!r}); channels found must match")
    if report.bank_hashes - {executive.bank_hash}:
        other = ", ".join(sorted(h[:12] for h in report.bank_hashes))
        mismatch(-1, f"the log was made with bank {other}, replayed with {executive.bank_hash[:12]}")
    return report


def _compare(report: ReplayReport, s, c: ComputedStatus, mismatch) -> None:
    report.statuses_compared += 1
    if tuple(s.hypothesis_names) != c.hypotheses:
        mismatch(s.frame, f"hypotheses on line differ: logged {list(s.hypothesis_names)}, "
                          f"replayed {list(c.hypotheses)}")
        return
    dp = float(np.max(np.abs(np.array(s.probabilities) - c.probabilities)))
    dz = float(np.max(np.abs(np.array(s.z_hat) - c.z_hat)))
    report.max_probability_diff = max(report.max_probability_diff, dp)
    report.max_z_hat_diff = max(report.max_z_hat_diff, dz)
    if not dp <= report.tolerance:
        mismatch(s.frame, f"probabilities differ by {dp:.3g} (tolerance {report.tolerance:g})")
    z_scale = max(1.0, float(np.max(np.abs(c.z_hat))))
    if not (dz <= report.tolerance * z_scale or math.isclose(dz, 0.0)):
        mismatch(s.frame, f"z_hat differs by {dz:.3g}")
    if s.bank_level != c.level:
        mismatch(s.frame, f"bank level {s.bank_level} in the log, {c.level} replayed")
    if s.declared != c.declared or s.declaration != c.declaration:
        mismatch(s.frame, f"declared {s.declared!r} (this frame {s.declaration!r}) in the log, "
                          f"{c.declared!r} ({c.declaration!r}) replayed")
    if bool(s.stale) != c.stale or s.frames_without_update != c.frames_without_update:
        mismatch(s.frame, f"stale flag: logged {bool(s.stale)} ({s.frames_without_update} frames), "
                          f"replayed {c.stale} ({c.frames_without_update})")
