"""Set-up once per flight condition: the trimmed aircraft each process keeps.

Loading and trimming JSBSim costs about as much as an 8-s flight, so each process keeps one
trimmed aircraft per (Mach, altitude, step) in ``POOL``.  A flight takes it (``acquire``),
``aircraft.restart`` returns it exactly to the state the trim left (with the flight's seed), and
the flight gives it back (``release``) when it ends; a second flight of the same condition at the
same time gets an aircraft of its own.
"""
from __future__ import annotations

import threading

from . import aircraft


class AircraftPool:
    """Trimmed aircraft (``core.JSBSimExec``, TrimPoint, ``aircraft.start_state``) kept per
    (mach, alt_ft, dt_s), at most one idle each; both engines fly them."""

    def __init__(self) -> None:
        self._idle: dict[tuple, tuple] = {}
        self._lock = threading.Lock()
        #: How many aircraft were loaded and trimmed (a measure of the set-up saved).
        self.trims = 0

    def acquire(self, mach: float, alt_ft: float, dt_s: float, seed: int):
        """(key, (fdm, trim_point, start)) at the trimmed start with ``seed`` (``aircraft.restart``)."""
        key = (float(mach), float(alt_ft), float(dt_s))
        with self._lock:
            held = self._idle.pop(key, None)
        if held is None:
            fdm = aircraft.load_fdm(seed=seed, dt_s=dt_s, cxx=True)
            held = (fdm, aircraft.trim(fdm, mach, alt_ft), aircraft.start_state(fdm))
            self.trims += 1
        aircraft.restart(*held, seed)
        return key, held

    def release(self, key: tuple, held: tuple) -> None:
        """Give an aircraft back for the next flight of its condition."""
        with self._lock:
            self._idle.setdefault(key, held)

    def discard(self, key: tuple, held: tuple) -> None:
        """Drop an aircraft a flight has taken away from its trim (a maneuvering flight)."""

    def clear(self) -> None:
        with self._lock:
            self._idle.clear()


#: The process's pool.
POOL = AircraftPool()
