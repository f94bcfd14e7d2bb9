"""Flights of the nonlinear truth model for design checks and tuning.

``fly_closed_loop`` (the tuning and report flights): ``truth.fly_raw`` -- the full truth
model (actuators, sensors, turbulence, the project's FCS on RAW sensor feedback, so no
estimator is in the loop, and its default dither) -- recorded as the (u, z) an estimator
sees, minus the trim.

``fly_open_loop`` (step responses, and a loop-free cross-check):

The truth airframe (derived JSBSim F-16) with the truth actuators (lags, limits, mixing),
sensors (noise) and turbulence, trimmed at the design point, flown WITHOUT a flight control
system: the surface commands are the trim plus a dither of sinusoids (one frequency per
surface), or a step on one surface. Open loop isolates the design model's mismatch from any
feedback loop; the bare airframe is stable at the nominal point, so 8-s flights stay near
trim. Each frame (FRAME_RATE_HZ) records ``z`` (sensors at t_i) and the command ``u_i`` held
over [t_i, t_{i+1}) -- the (u, z) an estimator sees -- as perturbations from the trim.

Failures (for the sensitivity checks of the design report) are injected into the truth
actuators / sensors with their ``complete`` mode; only the truth sees them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import names
from ..truth import actuators, aircraft, sensors, turbulence
from ..truth.dither import DitherSpec
from ..truth.failures import FailureSpec
from ..truth.model import fly_raw
from ..truth.scenario import Scenario

#: Default dither of the open-loop flights: amplitude (deg) and frequency (Hz) per surface,
#: LS RS LF RF RUD; distinct, non-harmonic frequencies in the 0.7-1.7 Hz band.
DITHER_AMPLITUDE_DEG = (0.5, 0.5, 0.5, 0.5, 0.5)
DITHER_FREQUENCY_HZ = (1.1, 0.7, 1.3, 0.9, 1.7)


@dataclass(frozen=True)
class Flight:
    """One flight's estimator inputs as perturbations from trim: ``u`` (n, 5), ``z`` (n, 7),
    ``z_ideal`` (n, 7, noise-free), ``time_s`` (n,)."""

    u: np.ndarray
    z: np.ndarray
    z_ideal: np.ndarray
    time_s: np.ndarray
    seed: int
    failure: str | None


def fly_open_loop(mach: float = 0.4, alt_ft: float = 20_000.0, *, seed: int = 1,
                  turbulence_level: str = "light", duration_s: float = 8.0,
                  dither: bool = True, step: tuple[str, float] | None = None,
                  failure: str | None = None, failure_time_s: float = 3.0,
                  noise: bool = True) -> Flight:
    """Fly the truth open loop. ``step=("LS", 0.0035)`` adds a step command (rad) at t = 0 on
    one surface; ``failure`` ("LS", "PIT", ...) fails that component completely at
    ``failure_time_s``."""
    fdm, trim = aircraft.trimmed_fdm(mach=mach, alt_ft=alt_ft, seed=seed)
    turbulence.apply(fdm, turbulence_level)
    sub = names.SIM_RATE_HZ // names.FRAME_RATE_HZ
    act = actuators.ActuatorBank(trim.u_rad, 1.0 / names.SIM_RATE_HZ)
    sens = sensors.SensorSet(fdm, trim.z, np.random.default_rng(seed), noise=noise)
    n = int(round(duration_s * names.FRAME_RATE_HZ))
    amp = np.radians(DITHER_AMPLITUDE_DEG) if dither else np.zeros(names.NU)
    freq = 2.0 * np.pi * np.asarray(DITHER_FREQUENCY_HZ)
    offset = np.zeros(names.NU)
    if step is not None:
        offset[names.ACTUATORS.index(step[0])] = step[1]
    u = np.zeros((n, names.NU))
    z = np.zeros((n, names.NZ))
    zi = np.zeros((n, names.NZ))
    failed = False
    for i in range(n):
        t = i / names.FRAME_RATE_HZ
        if failure is not None and not failed and t >= failure_time_s:
            if failure in names.ACTUATORS:
                act.fail(names.ACTUATORS.index(failure), "complete")
            else:
                sens.fail(names.SENSORS.index(failure), "complete", None, t)
            failed = True
        zi[i] = sens.ideal()
        z[i] = sens.measure(t)
        u[i] = trim.u_rad + offset + amp * np.sin(freq * t)
        for _ in range(sub):
            aircraft.set_surfaces(fdm, act.step(u[i]))
            fdm.run()
    return Flight(u=u - trim.u_rad, z=z - trim.z, z_ideal=zi - trim.z,
                  time_s=np.arange(n) / names.FRAME_RATE_HZ, seed=seed, failure=failure)


def fly_closed_loop(mach: float = 0.4, alt_ft: float = 20_000.0, *, seed: int = 1,
                    turbulence_level: str = "light", duration_s: float = 8.0,
                    failure: str | None = None, failure_time_s: float = 3.0,
                    dither: DitherSpec | None = None, ari: bool = True) -> Flight:
    """Fly the full truth model with its FCS on raw feedback and its default dither (or
    ``dither``); ``failure`` ("LS", "PIT", ...) fails that component completely at
    ``failure_time_s``; ``ari`` switches the aileron-to-rudder interconnect."""
    failures = () if failure is None else (FailureSpec(failure, failure_time_s, "complete"),)
    sc = Scenario(mach=mach, alt_ft=alt_ft, turbulence=turbulence_level, seed=seed,
                  duration_s=duration_s, feedback="raw", failures=failures, ari=ari,
                  dither=dither if dither is not None else DitherSpec())
    truth, _ = fly_raw(sc)
    log = truth.truth_log
    n = len(log["u_cmd_rad"])
    trim = truth.trim
    return Flight(u=log["u_cmd_rad"] - trim.u_rad, z=log["z"][:n] - trim.z,
                  z_ideal=log["z_ideal"][:n] - trim.z, time_s=log["time_s"][:n], seed=seed,
                  failure=failure)
