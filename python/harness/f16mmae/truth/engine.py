"""Which code flies the truth model's frames, and the trimmed aircraft kept per flight condition.

Engines (``ENGINES``):

``cpp`` (default)
    The per-step path (sensors, flight control law, dither, actuators, failures) in C++
    (``cpp/truth/truth_frame.h``), stepping JSBSim from C++ (``f16mmae.core.TruthFrames`` over a
    ``core.JSBSimExec``): one Python call per frame, or one per flight (``fly_raw``).
``python``
    The reference: the same model in this package's Python (``actuators``, ``sensors``,
    ``fcs``, ``dither``) on a ``jsbsim.FGFDMExec``.  Slower (about 12 us of Python per frame);
    kept as the readable statement of the model and the yardstick of the C++ path
    (tests/python/test_truth_engines.py flies both and requires the same flights).

Both fly the same JSBSim aircraft, a ``core.JSBSimExec`` (the ``jsbsim`` package's library made
and stepped from C++), set up by the same code (``aircraft``); select with
``TruthModel(scenario, engine=...)`` or the environment variable ``F16MMAE_TRUTH_ENGINE``.

Set-up once per flight condition: loading and trimming JSBSim costs about as much as an 8-s
flight, so each process keeps one trimmed aircraft per (Mach, altitude, step) in ``POOL``.  A
flight takes it (``acquire``), ``aircraft.restart`` returns it exactly to the state the trim left
(with the flight's seed), and the flight gives it back (``release``) when it ends; a second
flight of the same condition at the same time gets an aircraft of its own.
"""
from __future__ import annotations

import os
import threading

ENGINES: tuple[str, ...] = ("cpp", "python")
#: Environment variable selecting the default engine.
ENGINE_ENV = "F16MMAE_TRUTH_ENGINE"


def default_engine() -> str:
    """The engine used when none is given: ``$F16MMAE_TRUTH_ENGINE`` or ``cpp``."""
    return check_engine(os.environ.get(ENGINE_ENV, "cpp"))


def check_engine(name: str | None) -> str:
    """``name`` if it is one of ENGINES (None: the default), else ValueError naming them."""
    if name is None:
        return default_engine()
    if name not in ENGINES:
        raise ValueError(f"unknown truth engine {name!r}; valid: {', '.join(ENGINES)}")
    return name


def jsbsim_exec(root_dir: str):
    """A ``core.JSBSimExec`` at ``root_dir``, after checking that the core was built against the
    jsbsim release installed (the C++ path calls into that release's library)."""
    import jsbsim

    from .. import core

    if core.JSBSIM_VERSION != jsbsim.__version__:
        raise RuntimeError(f"f16mmae.core was built against jsbsim {core.JSBSIM_VERSION} but jsbsim "
                           f"{jsbsim.__version__} is installed: rebuild (make build) or choose "
                           f"{ENGINE_ENV}=python")
    return core.JSBSimExec(root_dir)


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
        from . import aircraft

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

    def clear(self) -> None:
        with self._lock:
            self._idle.clear()


#: The process's pool.
POOL = AircraftPool()
