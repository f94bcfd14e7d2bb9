"""The MMAE executive over LCM, as the estimator the closed loop calls."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..lcmt_mmae_reset import lcmt_mmae_reset
from ..lcmt_mmae_status import lcmt_mmae_status
from ..names import FRAME_RATE_HZ, NZ
from .channels import Channels, HilError
from .codec import command_frame_bytes, sensor_frame_bytes


@dataclass
class LinkStats:
    """What the link did during one flight."""
    frames: int = 0
    latency_ns: list[int] = field(default_factory=list)   # sensor publish -> status received
    deadline_misses: int = 0                               # paced: no status before the next frame
    stale_statuses: int = 0                                # statuses the executive marked stale
    unauthenticated_statuses: int = 0                      # with a key: statuses dropped, no valid tag
    replayed_statuses: int = 0                             # with a key: statuses dropped, old sequence
    air_data_rejected: int = 0                             # the executive's count at the last status

    def summary(self) -> dict:
        lat = np.array(self.latency_ns, dtype=float) / 1e3
        q = (lambda p: round(float(np.percentile(lat, p)), 1)) if lat.size else (lambda p: None)
        return {"frames": self.frames, "statuses": int(lat.size), "deadline_misses": self.deadline_misses,
                "stale_statuses": self.stale_statuses,
                "unauthenticated_statuses": self.unauthenticated_statuses,
                "replayed_statuses": self.replayed_statuses,
                "air_data_rejected": self.air_data_rejected,
                "latency_us": {"p50": q(50), "p99": q(99), "max": round(float(lat.max()), 1) if lat.size else None}}


class RemoteEstimator:
    """The MMAE executive over LCM, with the interface :func:`f16mmae.loop.flight.fly` calls
    (``schedule(mach, pressure_altitude_ft)``, ``update(z) -> z_hat``, ``propagate(u)``,
    ``hypotheses``, ``probabilities``, ``declared``, ``bank_hash``; with a turbulence bank set
    ``turbulence_member`` and ``turbulence_power_ratio``, the adaptive dither's input, read off the
    status). Only u, z and the measured
    air data cross the link: ``schedule`` keeps the air data that the next ``update`` sends in
    its sensor frame (NaN until the first ``schedule``: the executive then keeps its bank's own).

    ``lockstep``: each update waits for its status up to ``timeout_s`` (HilError after).
    Paced: frame i is published at ``t0 + i / rate_hz`` and its status awaited until the next
    frame is due; a miss leaves z_hat and the probabilities at their last values (before the
    first status, z_hat is the raw z: what an FCS falls back to without its estimator).

    ``auth`` (a ``core.FrameAuth``): every frame and reset sent is signed, and a status is used
    only when its tag and sequence check out (others are dropped and counted in ``link``)."""

    def __init__(self, lc, chans: Channels, *, lockstep: bool = True, rate_hz: float = FRAME_RATE_HZ,
                 timeout_s: float = 5.0, expected_bank_hash: str | None = None,
                 initial_hypotheses: tuple[str, ...] = (), auth=None) -> None:
        self._lc, self._ch = lc, chans
        self._auth = auth
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
        self._air_data = (math.nan, math.nan)
        self.link = LinkStats()
        #: The estimator settings the executive is presumed to run (the record's estimator_settings).
        self.settings: dict = {}
        self._sub = lc.subscribe(chans.status, self._on_status)

    def close(self) -> None:
        if self._sub is not None:
            self._lc.unsubscribe(self._sub)
            self._sub = None

    # -- LCM side
    def _publish(self, channel: str, data: bytes) -> None:
        self._lc.publish(channel, self._auth.sign(channel, data) if self._auth is not None else data)

    def _on_status(self, channel, data) -> None:
        t = time.perf_counter_ns()
        if self._auth is not None:
            verdict = self._auth.check(channel, data)
            if verdict != "ok":
                if verdict == "replayed":
                    self.link.replayed_statuses += 1
                else:
                    self.link.unauthenticated_statuses += 1
                return
        msg = self._decode(data)
        if msg.frame != self._frame or (self._status is not None and self._status.frame == self._frame):
            return  # an old frame's status (or a repeat): not ours to use
        self.link.latency_ns.append(t - self._t_pub)
        if msg.stale:
            self.link.stale_statuses += 1
        self.link.air_data_rejected = msg.air_data_rejected
        self._status = msg

    def frame_due(self, i: float) -> float | None:
        """Paced mode: the perf_counter time at which frame i (may be fractional) is due."""
        return None if self._t0 is None else self._t0 + i / self.rate_hz

    def reset(self, reason: str = "") -> None:
        """A new flight on the executive (MMAE_RESET); frame counting restarts at 0."""
        msg = lcmt_mmae_reset()
        msg.utime = 0
        msg.reason = reason
        self._publish(self._ch.reset, msg.encode())
        self._frame = -1
        self._status = None
        self._t0 = None
        self._air_data = (math.nan, math.nan)

    # -- the estimator interface
    def schedule(self, mach, pressure_altitude_ft) -> None:
        self._air_data = (float(mach), float(pressure_altitude_ft))

    def update(self, z) -> np.ndarray:
        z = np.array(z, dtype=float).reshape(-1)
        self._frame += 1
        i = self._frame
        data = sensor_frame_bytes(i, z, self._air_data, rate_hz=self.rate_hz)
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
        self._publish(self._ch.sensors, data)
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
        self._publish(self._ch.commands, command_frame_bytes(self._frame, u, self.rate_hz))

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
    def turbulence_member(self) -> int | None:
        """The turbulence bank set's member in force after the last update (the status's
        ``turbulence_member``), None before the first status or when the executive runs no set."""
        if self._status is None or self._status.turbulence_member < 0:
            return None
        return int(self._status.turbulence_member)

    @property
    def turbulence_power_ratio(self) -> float:
        """That member's residual power ratio rho, or one adapted bank's measured rho-bar (the
        status's ``turbulence_power_ratio``); NaN before the first status or without either."""
        return float(self._status.turbulence_power_ratio) if self._status is not None else math.nan

    @property
    def measured_power_ratio(self) -> float:
        """The measured residual power ratio the air is read by, as the in-process estimator's
        (loop/estimator.py): the status's ``turbulence_power_ratio``."""
        return self.turbulence_power_ratio

    @property
    def bank_hash(self) -> str:
        return self._status.bank_hash if self._status is not None else (self.expected_bank_hash or "")


def level0_hypotheses(model_bank) -> tuple[str, ...]:
    """NONE and the single failures, in the bank's order (the executive's level 0)."""
    names = [h.name for h in model_bank.hypotheses]
    return tuple(n for n in names if "+" not in n)
