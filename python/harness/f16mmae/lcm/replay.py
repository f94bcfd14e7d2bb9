"""Replay recorded executive traffic through the in-process executive and compare, frame by frame.

A log written by the stock ``lcm-logger`` (or any LCM event log) holds the sensor frames,
command frames and status frames of a flight. :func:`replay_log` feeds the sensor and
command frames, in log order, through :class:`InProcessExecutive` -- ``mmae-daemon``'s own
C++ executive (``core.Executive``, cpp/executive/executive.h: its frame rules, its estimator,
its status encoding) -- and compares each logged status with the one computed here for the
same frame: hypothesis names, bank level, declaration, stale and re-synchronisation flags, the
turbulence set's member in force and its rho (to the tolerance, relative above 1), and
the largest absolute difference of the probabilities and of z_hat. A reset on MMAE_RESET
starts a new flight, as on the daemon.

:class:`InProcessExecutive` can also answer over LCM (:meth:`InProcessExecutive.serve`), so
the harness's LCM path is testable in one process over ``memq://``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import lcm
import numpy as np

from .. import core
from ..banks import bank_estimator_settings
from ..errors import F16mmaeError
from ..lcmt_command_frame import lcmt_command_frame
from ..lcmt_mmae_status import lcmt_mmae_status
from ..lcmt_sensor_frame import lcmt_sensor_frame
from ..loop.estimator import core_arguments, flown_bank_hash, turbulence_set_of
from ..loop.estimator_options import CLOSED_LOOP
from .channels import Channels, channels
from .codec import command_of


class ReplayError(F16mmaeError, RuntimeError):
    """The log cannot be read or does not hold executive traffic."""


class InProcessExecutive:
    """``core.Executive`` (the daemon's executive) with the estimator settings the daemon
    applies: the bank's recommended ones, then ``estimator_options`` (which win): any option of
    the estimator's table (``loop.estimator_options``: adapt_turbulence, adapt_reference,
    trim_time_constant_s, actuator_limits, ...), as ``mmae-daemon``'s flags set them; with
    ``turbulence_banks`` the turbulence bank set whose member ``model_bank`` is, from its file
    (``mmae-daemon --bank SET --turbulence-banks``)."""

    def __init__(self, model_bank, **estimator_options) -> None:
        settings = bank_estimator_settings(model_bank, estimator_options)
        self.bank_hash = flown_bank_hash(model_bank, settings)
        for key in CLOSED_LOOP:   # the closed loop's (the truth side's), not the executive's
            settings.pop(key, None)
        arguments = core_arguments(settings, model_bank.nu)   # reads turbulence_banks (the set's tempering)
        source = turbulence_set_of(model_bank).source if arguments.pop("turbulence_banks", False) else model_bank
        # a scheduled bank's per-node floors unless a p_min was given (then that everywhere)
        self.executive = core.Executive(source, **arguments, node_p_min="p_min" not in estimator_options)

    def reset(self) -> None:
        self.executive.on_reset()

    def on_sensor(self, frame: int, z, valid=None, utime: int = 0, air_data=None) -> lcmt_mmae_status | None:
        """The status this sensor frame produces (decoded), or None when it produces none.
        ``air_data``: the frame's (mach, pressure_altitude_ft); None as a frame without them (NaN)."""
        air = None if air_data is None else [float(v) for v in air_data]
        fate = self.executive.on_sensor(int(frame), np.asarray(z, dtype=float), valid, int(utime), air)
        if fate not in ("used", "resynchronised"):
            return None
        return lcmt_mmae_status.decode(self.executive.encoded_status)

    def on_command(self, frame: int, u, utime: int = 0) -> str:
        """The command frame's fate ("used", "rejected", ...). ``u``: the five surface commands,
        then the throttle command (six; needed by a bank that models the throttle)."""
        return self.executive.on_command(int(frame), np.asarray(u, dtype=float), int(utime))

    def serve(self, lc, chans: Channels) -> list:
        """Subscribe to the sensor, command and reset channels of ``lc`` and publish statuses,
        as mmae-daemon does (the same bytes). Returns the subscriptions (unsubscribe to stop)."""
        def on_sensor(channel, data):
            f = lcmt_sensor_frame.decode(data)
            fate = self.executive.on_sensor(f.frame, np.asarray(f.z, dtype=float), list(f.valid), f.utime,
                                            [f.mach, f.pressure_altitude_ft])
            if fate in ("used", "resynchronised"):
                lc.publish(chans.status, self.executive.encoded_status)

        def on_command(channel, data):
            f = lcmt_command_frame.decode(data)
            self.on_command(f.frame, command_of(f), f.utime)

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
    unauthenticated: int = 0             # with a key: messages without a valid tag, skipped
    replayed: int = 0                    # with a key: messages with an old sequence, skipped
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
               max_mismatches: int = 20, auth=None, **estimator_options) -> ReplayReport:
    """Feed the logged frames through the in-process executive; compare with the logged
    statuses. With ``auth`` (a ``core.FrameAuth``), a logged frame, reset or status is used
    only if its tag and sequence check out, as the daemon and the harness check them; the
    others are skipped and counted (``unauthenticated``, ``replayed``)."""
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
    computed: dict[int, lcmt_mmae_status] = {}
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
        link = {chans.sensors, chans.commands, chans.reset, chans.status}
        for event in log:
            report.events += 1
            ch = event.channel
            if auth is not None and ch in link and (verdict := auth.check(ch, event.data)) != "ok":
                if verdict == "replayed":
                    report.replayed += 1
                else:
                    report.unauthenticated += 1
                continue
            if ch == chans.sensors:
                f = _decode(lcmt_sensor_frame, event.data, path)
                report.sensor_frames += 1
                c = executive.on_sensor(f.frame, f.z, list(f.valid), f.utime, (f.mach, f.pressure_altitude_ft))
                if c is not None:
                    if c.frame in early:  # its status was logged before the frame itself
                        _compare(report, early.pop(c.frame), c, mismatch)
                    else:
                        computed[c.frame] = c
            elif ch == chans.commands:
                f = _decode(lcmt_command_frame, event.data, path)
                report.command_frames += 1
                executive.on_command(f.frame, command_of(f), f.utime)
            elif ch == chans.reset:
                executive.reset()
                computed.clear()
                unmatched(early)
            elif ch == chans.status:
                s = _decode(lcmt_mmae_status, event.data, path)
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


#: The fingerprints (first 8 bytes) of the messages' former versions, which this version cannot
#: replay, and what the current version carries that they lack (docs/INTERFACES.md).
SENSOR_FRAME_FINGERPRINT_WITHOUT_AIR_DATA = bytes.fromhex("23052c572d827754")
COMMAND_FRAME_FINGERPRINT_WITHOUT_THROTTLE = bytes.fromhex("7104f132bac68b60")
STATUS_FINGERPRINT_WITHOUT_TURBULENCE_MEMBER = bytes.fromhex("4b2dcf092b651b13")
FORMER_VERSIONS = {
    lcmt_sensor_frame: (SENSOR_FRAME_FINGERPRINT_WITHOUT_AIR_DATA,
                        "air data (mach, pressure_altitude_ft)"),
    lcmt_command_frame: (COMMAND_FRAME_FINGERPRINT_WITHOUT_THROTTLE, "the throttle command"),
    lcmt_mmae_status: (STATUS_FINGERPRINT_WITHOUT_TURBULENCE_MEMBER,
                       "the turbulence set's member in force and its rho"),
}


def _decode(message_type, data: bytes, path: Path):
    """A logged message of ``message_type``, or ReplayError naming the log when it was written
    by a former version of that message (``FORMER_VERSIONS``)."""
    fingerprint, lacked = FORMER_VERSIONS[message_type]
    if data[:8] == fingerprint:
        raise ReplayError(f"log {str(path)!r} was recorded before {message_type.__name__} carried {lacked} "
                          f"(docs/INTERFACES.md): it cannot be replayed by this version; record the flight "
                          f"again (f16mmae hil) or replay it with the release that wrote it")
    return message_type.decode(data)


def _compare(report: ReplayReport, s, c: lcmt_mmae_status, mismatch) -> None:
    """Logged status ``s`` against the one computed here, ``c``, for the same frame."""
    report.statuses_compared += 1
    if list(s.hypothesis_names) != list(c.hypothesis_names):
        mismatch(s.frame, f"hypotheses on line differ: logged {list(s.hypothesis_names)}, "
                          f"replayed {list(c.hypothesis_names)}")
        return
    c_z_hat = np.array(c.z_hat)
    dp = float(np.max(np.abs(np.array(s.probabilities) - np.array(c.probabilities))))
    dz = float(np.max(np.abs(np.array(s.z_hat) - c_z_hat)))
    report.max_probability_diff = max(report.max_probability_diff, dp)
    report.max_z_hat_diff = max(report.max_z_hat_diff, dz)
    if not dp <= report.tolerance:
        mismatch(s.frame, f"probabilities differ by {dp:.3g} (tolerance {report.tolerance:g})")
    z_scale = max(1.0, float(np.max(np.abs(c_z_hat))))
    if not (dz <= report.tolerance * z_scale or math.isclose(dz, 0.0)):
        mismatch(s.frame, f"z_hat differs by {dz:.3g}")
    if s.bank_level != c.bank_level:
        mismatch(s.frame, f"bank level {s.bank_level} in the log, {c.bank_level} replayed")
    if s.declared != c.declared or s.declaration != c.declaration:
        mismatch(s.frame, f"declared {s.declared!r} (this frame {s.declaration!r}) in the log, "
                          f"{c.declared!r} ({c.declaration!r}) replayed")
    if bool(s.stale) != bool(c.stale) or s.frames_without_update != c.frames_without_update:
        mismatch(s.frame, f"stale flag: logged {bool(s.stale)} ({s.frames_without_update} frames), "
                          f"replayed {bool(c.stale)} ({c.frames_without_update})")
    if s.air_data_rejected != c.air_data_rejected:
        mismatch(s.frame, f"air data rejected: logged {s.air_data_rejected}, replayed {c.air_data_rejected}")
    if s.turbulence_member != c.turbulence_member:
        mismatch(s.frame, f"turbulence set member in force: logged {s.turbulence_member}, "
                          f"replayed {c.turbulence_member}")
    rho_s, rho_c = float(s.turbulence_power_ratio), float(c.turbulence_power_ratio)
    if not (abs(rho_s - rho_c) <= report.tolerance * max(1.0, abs(rho_c))
            or (math.isnan(rho_s) and math.isnan(rho_c))):
        mismatch(s.frame, f"turbulence power ratio rho: logged {rho_s:.9g}, replayed {rho_c:.9g}")
    if bool(s.resynchronised) != bool(c.resynchronised):
        mismatch(s.frame, f"re-synchronisation: logged {bool(s.resynchronised)}, "
                          f"replayed {bool(c.resynchronised)}")
