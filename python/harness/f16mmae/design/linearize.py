"""Linearization of the bare F-16 airframe about a trim, by central finite differences and
by JSBSim's own ``FGLinearization`` (the cross-check).

Airframe states (``names.STATES[:8]``, perturbations about the trim)::

    x_a = [u_fps, alpha_rad, q_rad_s, theta_rad | beta_rad, p_rad_s, r_rad_s, phi_rad]

inputs the five surface deflections ``d = [LS, RS, LF, RF, RUD]`` (rad), outputs the seven
noise-free sensor readings ``z`` (``names.SENSORS``)::

    x_a' = A x_a + B d,        z = C x_a + D d

Finite differences: each state and surface is displaced by +/- its step from the trim and
the model re-initialized with ``run_ic()`` (integration suspended, so nothing moves); the
state derivative is read from ``accelerations/{u,v,w,p,q,r}dot`` and
``velocities/{theta,phi}dot`` and mapped to (u, alpha, beta) exactly:
``alpha' = (u w' - w u') / (u^2 + w^2)``, ``beta' = (v' - v V'/V) / (V cos beta)``.
Central differences ``(f(x+h) - f(x-h)) / 2h``: 1 + 2 (8 + 5) = 27 evaluations.
Altitude, heading and position are held (the reduced model omits them, paper Sec. IV).

The velocity is body-axis, so the airframe's wind sensitivity follows from the same data:
aerodynamic and propulsive forces depend on the air-relative velocity, and at a level,
wings-level trim (p = q = r = 0) nothing else in x_a' depends on the velocity, so a body
gust ``(u_g, v_g, w_g)`` enters as ``-dx_a'/d(u, v, w)`` (see ``gust_input``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .. import names
from ..truth import aircraft

SurfaceSetter = Callable[[object, np.ndarray], None]
Measure = Callable[[object], np.ndarray]

#: Airframe state order of this module (the first eight of names.STATES).
AIRFRAME_STATES: tuple[str, ...] = names.STATES[:8]

#: Central-difference steps: states (u ft/s, angles rad, rates rad/s), surfaces rad.
STATE_STEPS = np.array([0.05, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4])
SURFACE_STEP_RAD = 1e-4


@dataclass(frozen=True)
class AirframeLinearization:
    """Bare-airframe model about a trim: ``x' = a x + b d``, ``z = c x + dd d``; also the
    body-axis velocity Jacobian ``a_uvw`` (8 x 3, columns u, v, w) for the gust input."""

    a: np.ndarray      # (8, 8)
    b: np.ndarray      # (8, 5)
    c: np.ndarray      # (7, 8)
    dd: np.ndarray     # (7, 5)
    a_uvw: np.ndarray  # (8, 3)
    c_uvw: np.ndarray  # (7, 3)
    x_trim: np.ndarray        # (8,) absolute trim: u, alpha, q, theta, beta, p, r, phi
    surfaces_trim: np.ndarray  # (5,) rad
    z_trim: np.ndarray         # (7,)
    evaluations: int


def _uvw(x: np.ndarray) -> tuple[float, float, float]:
    u, alpha, beta = x[0], x[1], x[4]
    w = u * np.tan(alpha)
    vt = np.hypot(u, w) / np.cos(beta)
    return float(u), float(vt * np.sin(beta)), float(w)


def read_state(fdm) -> np.ndarray:
    """Absolute airframe state of ``fdm`` in this module's order (inertial, no wind)."""
    u, v, w = fdm["velocities/u-fps"], fdm["velocities/v-fps"], fdm["velocities/w-fps"]
    vt = np.sqrt(u * u + v * v + w * w)
    return np.array([u, np.arctan2(w, u), fdm["velocities/q-rad_sec"], fdm["attitude/theta-rad"],
                     np.arcsin(v / vt), fdm["velocities/p-rad_sec"], fdm["velocities/r-rad_sec"],
                     fdm["attitude/phi-rad"]])


def set_state(fdm, x: np.ndarray) -> None:
    """Write an absolute airframe state into the initial conditions (angles first, so the
    body velocities written after them are kept)."""
    fdm["ic/theta-rad"] = float(x[3])
    fdm["ic/phi-rad"] = float(x[7])
    u, v, w = _uvw(x)
    fdm["ic/u-fps"], fdm["ic/v-fps"], fdm["ic/w-fps"] = u, v, w
    fdm["ic/p-rad_sec"], fdm["ic/q-rad_sec"], fdm["ic/r-rad_sec"] = (
        float(x[5]), float(x[2]), float(x[6]))


def state_derivative(fdm) -> np.ndarray:
    """``x_a'`` of the current (re-initialized) model in this module's order."""
    u, v, w = fdm["velocities/u-fps"], fdm["velocities/v-fps"], fdm["velocities/w-fps"]
    ud, vd, wd = (fdm["accelerations/udot-ft_sec2"], fdm["accelerations/vdot-ft_sec2"],
                  fdm["accelerations/wdot-ft_sec2"])
    vt = np.sqrt(u * u + v * v + w * w)
    vtd = (u * ud + v * vd + w * wd) / vt
    alpha_d = (u * wd - w * ud) / (u * u + w * w)
    beta_d = (vd - v * vtd / vt) / (vt * np.sqrt(1.0 - (v / vt) ** 2))
    return np.array([ud, alpha_d, fdm["accelerations/qdot-rad_sec2"],
                     fdm["velocities/thetadot-rad_sec"], beta_d, fdm["accelerations/pdot-rad_sec2"],
                     fdm["accelerations/rdot-rad_sec2"], fdm["velocities/phidot-rad_sec"]])


def finite_difference(fdm, set_surfaces: SurfaceSetter, measure: Measure,
                      surfaces_trim: np.ndarray) -> AirframeLinearization:
    """Central-difference linearization of a trimmed ``fdm`` whose surfaces ``set_surfaces``
    writes directly (no actuator dynamics) and whose ideal sensors ``measure`` reads.

    The model is left re-initialized at the trim."""
    x0 = read_state(fdm)
    d0 = np.asarray(surfaces_trim, dtype=float).copy()
    count = 0

    def evaluate(x: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nonlocal count
        set_state(fdm, x)
        set_surfaces(fdm, d)
        fdm.run_ic()
        count += 1
        return state_derivative(fdm), np.asarray(measure(fdm), dtype=float)

    _, z0 = evaluate(x0, d0)
    nx, nd, nz = len(x0), len(d0), len(z0)
    a, c = np.zeros((nx, nx)), np.zeros((nz, nx))
    for j in range(nx):
        h = STATE_STEPS[j]
        e = np.zeros(nx)
        e[j] = h
        fp, zp = evaluate(x0 + e, d0)
        fm, zm = evaluate(x0 - e, d0)
        a[:, j], c[:, j] = (fp - fm) / (2 * h), (zp - zm) / (2 * h)
    b, dd = np.zeros((nx, nd)), np.zeros((nz, nd))
    for j in range(nd):
        e = np.zeros(nd)
        e[j] = SURFACE_STEP_RAD
        fp, zp = evaluate(x0, d0 + e)
        fm, zm = evaluate(x0, d0 - e)
        b[:, j], dd[:, j] = (fp - fm) / (2 * SURFACE_STEP_RAD), (zp - zm) / (2 * SURFACE_STEP_RAD)
    evaluate(x0, d0)  # leave the model at the trim
    count -= 1
    jac = uvw_jacobian(x0)  # d(u, alpha, beta)/d(u, v, w) rows for states 0, 1, 4
    a_uvw = a[:, [0, 1, 4]] @ jac
    c_uvw = c[:, [0, 1, 4]] @ jac
    return AirframeLinearization(a=a, b=b, c=c, dd=dd, a_uvw=a_uvw, c_uvw=c_uvw, x_trim=x0,
                                 surfaces_trim=d0, z_trim=z0, evaluations=count)


def uvw_jacobian(x: np.ndarray) -> np.ndarray:
    """``d(u, alpha, beta) / d(u, v, w)`` (3 x 3) at the absolute state ``x``."""
    u, v, w = _uvw(x)
    vt2 = u * u + v * v + w * w
    uw2 = u * u + w * w
    return np.array([
        [1.0, 0.0, 0.0],
        [-w / uw2, 0.0, u / uw2],
        [-u * v / (vt2 * np.sqrt(uw2)), np.sqrt(uw2) / vt2, -w * v / (vt2 * np.sqrt(uw2))],
    ])


# JSBSim FGLinearization states: Vt Alpha Theta Q Beta Phi P Psi R Latitude Longitude Alt.
_JSB_INDEX = {"Vt": 0, "Alpha": 1, "Theta": 2, "Q": 3, "Beta": 4, "Phi": 5, "P": 6, "R": 8}


def jsbsim_linearization(fdm) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """JSBSim's ``FGLinearization`` of the trimmed ``fdm``, mapped to this module's state
    order and coordinates: returns ``(A (8x8), B (8 x its inputs), its input names)``.

    ``FGLinearization`` uses (Vt, alpha, beta); the map to (u, alpha, beta) is
    ``du = cos a cos b dVt - Vt sin a cos b da - Vt cos a sin b db``, so ``A = T A_j T^-1``.
    Its inputs are the pilot commands (throttle, aileron, elevator, rudder) as the
    aircraft's flight control section passes them on: its trim-command terms are switched on
    for it (``aircraft.TRIM_COMMANDS_PROPERTY``, off again afterwards as the trim left them)."""
    import jsbsim

    was = fdm[aircraft.TRIM_COMMANDS_PROPERTY]
    fdm[aircraft.TRIM_COMMANDS_PROPERTY] = 1
    try:
        lin = jsbsim.FGLinearization(fdm)
    finally:
        fdm[aircraft.TRIM_COMMANDS_PROPERTY] = was
    names_j = tuple(lin.x_names)
    order = ["Vt", "Alpha", "Q", "Theta", "Beta", "P", "R", "Phi"]
    idx = [names_j.index(n) for n in order]
    a_j = np.asarray(lin.system_matrix)[np.ix_(idx, idx)]
    b_j = np.asarray(lin.input_matrix)[idx, :]
    x0 = np.asarray(lin.x0)
    vt, alpha, beta = x0[names_j.index("Vt")], x0[names_j.index("Alpha")], x0[names_j.index("Beta")]
    t = np.eye(8)
    t[0, 0] = np.cos(alpha) * np.cos(beta)
    t[0, 1] = -vt * np.sin(alpha) * np.cos(beta)
    t[0, 4] = -vt * np.cos(alpha) * np.sin(beta)
    return t @ a_j @ np.linalg.inv(t), t @ b_j, tuple(lin.u_names)


#: JSBSim's name of the throttle command among FGLinearization's inputs.
THROTTLE_INPUT_JSBSIM = "ThtlCmd"


def throttle_column(fdm) -> np.ndarray:
    """(8,) ``b_th``: the throttle command's column of JSBSim's linearization of the trimmed
    ``fdm`` (:func:`jsbsim_linearization`), airframe state order u alpha q theta beta p r phi,
    per unit command (0..1).  The turbine reaches its new thrust within a frame at dither
    amplitudes (design/excitation.py), so the column is a direct input: no engine state."""
    _, b, inputs = jsbsim_linearization(fdm)
    if THROTTLE_INPUT_JSBSIM not in inputs:
        raise RuntimeError(f"JSBSim's linearization inputs are {inputs}, expected {THROTTLE_INPUT_JSBSIM}")
    return np.asarray(b[:, inputs.index(THROTTLE_INPUT_JSBSIM)], dtype=float)
