"""Dryden gust states inside the filters (``gust_model`` ``dryden_states``, 19 states, and
``dryden_translational``, 16): the turbulence as shaping-filter states rather than white noise.

The zero-order models of ``model.py`` make the gust white (or its rate white); real gusts are
coloured, and the rotational gusts, which they leave out, drive the roll, pitch and yaw rates
through the aerodynamic damping, the signature of a flaperon or stabilator failure. Here the
gusts are states, appended after ``names.STATES`` in the turbulence axes (the local
north-east-down axes; the aircraft flies north at the trim, ``GUST_STATES``), with the MIL-STD-1797A
first-order forms of the MIL-F-8785C Dryden spectra (scale length L, wingspan b, airspeed V,
intensities sigma of the design level, ``n_*`` white)::

    u_g' = -(V/L) u_g + n_u              Q = 2 (V/L) sigma_u^2        (var u_g = sigma_u^2)
    v_g' = -(2V/L) v_g + n_v             Q = 2 (2V/L) sigma_v^2
    w_g' = -(2V/L) w_g + n_w             Q = 2 (2V/L) sigma_w^2
    p_g' = -(V/L_p) p_g + n_p            L_p = sqrt(L b) / 2.6,  sigma_p = 1.9 sigma_w / sqrt(L b)
    q_g' = -(V/L_p) q_g + n_q            Q_p = Q_q = 2 (V/L_p) (sigma_p^2 + sigma_q^2) / 2
    r_g' = -(v_g'/V + r_g) / tau_r       tau_r = 3 b / (pi V)   (driven by n_v through v_g')

where sigma_q^2 = pi sigma_w^2 / (2 b L) is the variance of MIL-F-8785C's pitch gust
q_g = (s/V) w_g / (1 + 4 b s / (pi V)). The roll and pitch gusts are heading-free: the truth
(JSBSim's Dryden model) defines its rotational gusts in the local axes, so on a heading other
than the turbulence axes' the roll gust p_g turns into pitch and q_g into roll; the estimator
does not know the heading, so both body components carry the average variance, as
independent first-order processes of the roll gust's break frequency V/L_p. Measured
(tools/gust_states/gust_residuals.py): a north-aligned model (q_g from w_g') fits the first minute of a
flight and then, as the aircraft drifts into a turn in moderate turbulence, its pitch-rate
residual variance grows to 7 times A; the heading-free one stays within 1.07-1.12 of A.
The sign of the yaw gust's coupling to v_g (r_g = -(s/V) v_g / (1 + tau_r s)) is the one
the truth's residuals choose (docs/results/gust_states.md); references differ on it.

How they enter (T = the body-from-local rotation at the trim attitude):

- translational: the velocity states (u, alpha, beta) are air-relative (``gust_rate``), so
  they gain ``-J T g_t'`` (J = d(u, alpha, beta)/d(u, v, w)): ``F[(u, alpha, beta), g_t] =
  -J T A_t`` and ``G[(u, alpha, beta), n_t] = -J T``, where ``g_t' = A_t g_t + n_t``;
- rotational: the aerodynamic moments and forces see the air-relative rates ``omega - T
  omega_g``, so the airframe rows gain ``-A_aero T omega_g`` and the accelerometer readings
  (AZ, AY: aerodynamic specific force) ``-C_aero T omega_g``. ``A_aero`` is the rate
  columns of the finite-difference A less their kinematic part at a level trim (p = q = r =
  v = phi = 0, body w = u tan alpha)::

      u' : -w q            alpha' : q             theta' : q
      beta' : (w p - u r)/V                        phi' : p + tan(theta) r

  and ``C_aero`` the rate columns of C in the accelerometer rows only (gyros and air data
  read the inertial rates).

``dryden_translational`` keeps the three translational states only (a measured comparison:
docs/results/gust_states.md).
"""
from __future__ import annotations

import math

import numpy as np

from .. import names
from .linearize import AirframeLinearization, uvw_jacobian

#: The six gust states, appended after ``names.STATES`` (turbulence axes: local N-E-D).
GUST_STATES: tuple[str, ...] = ("u_g_fps", "v_g_fps", "w_g_fps", "p_g_rad_s", "q_g_rad_s", "r_g_rad_s")
#: Gust model -> its gust states (a prefix of GUST_STATES).
GUST_STATE_MODELS: dict[str, tuple[str, ...]] = {
    "dryden_translational": GUST_STATES[:3],
    "dryden_states": GUST_STATES,
}
#: The F-16's wingspan (ft), as in the truth's aircraft data.
WINGSPAN_FT = 30.0
#: Accelerometer channels: their readings see the aerodynamic rates (module docstring).
ACCELEROMETERS: tuple[str, ...] = ("AZ", "AY")
# airframe state indices (names.STATES)
_U, _ALPHA, _Q, _THETA, _BETA, _P, _R, _PHI = range(8)


def kinematic_rate_columns(x_trim: np.ndarray) -> np.ndarray:
    """(8, 3) the kinematic part of dx_a'/d(p, q, r) at a level trim (module docstring)."""
    u, alpha, theta = x_trim[_U], x_trim[_ALPHA], x_trim[_THETA]
    w = u * math.tan(alpha)
    vt = math.hypot(u, w)
    k = np.zeros((8, 3))
    k[_U, 1] = -w
    k[_ALPHA, 1] = 1.0
    k[_THETA, 1] = 1.0
    k[_BETA, 0], k[_BETA, 2] = w / vt, -u / vt
    k[_PHI, 0], k[_PHI, 2] = 1.0, math.tan(theta)
    return k


def body_from_local(theta: float) -> np.ndarray:
    """(3, 3) body axes from local N-E-D axes, heading north, wings level, pitch ``theta``."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def augment(gust_model: str, lin: AirframeLinearization, vt_fps: float, sigma_fps: np.ndarray,
            scale_ft: float, n_plant: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The gust-state blocks of a model with ``n_plant`` states before them:
    ``(F_xg (n_plant + ng, ng) columns of the gust states, G (n_plant + ng, nw) the white
    inputs, Q_c (nw, nw), H_g (7, ng))``; nw = 3 translational noises, + 2 (n_p, n_q) with
    the rotational states."""
    states = GUST_STATE_MODELS[gust_model]
    ng = len(states)
    rotational = ng == 6
    nw = 5 if rotational else 3
    su, sv, sw = np.asarray(sigma_fps, dtype=float)
    v, length, span = float(vt_fps), float(scale_ft), WINGSPAN_FT
    a_t = np.array([v / length, 2.0 * v / length, 2.0 * v / length])
    t_bl = body_from_local(float(lin.x_trim[_THETA]))
    n = n_plant + ng
    f = np.zeros((n, ng))
    g = np.zeros((n, nw))
    jt = uvw_jacobian(lin.x_trim) @ t_bl
    rows = [_U, _ALPHA, _BETA]
    f[rows, 0:3] = jt * a_t          # -J T (-diag a_t)
    g[rows, 0:3] = -jt
    f[n_plant:n_plant + 3, 0:3] = -np.diag(a_t)
    g[n_plant:n_plant + 3, 0:3] = np.eye(3)
    qc = [2.0 * a_t[0] * su * su, 2.0 * a_t[1] * sv * sv, 2.0 * a_t[2] * sw * sw]
    h = np.zeros((len(names.SENSORS), ng))
    if rotational:
        l_p = math.sqrt(length * span) / 2.6
        a_p = v / l_p
        sigma_p = 1.9 * sw / math.sqrt(length * span)
        sigma_q2 = math.pi * sw * sw / (2.0 * span * length)
        var_pq = 0.5 * (sigma_p * sigma_p + sigma_q2)
        tau_r = 3.0 * span / (math.pi * v)
        a_aero = lin.a[:, [_P, _Q, _R]] - kinematic_rate_columns(lin.x_trim)
        f[:8, 3:6] = -a_aero @ t_bl
        ip, iq, ir = n_plant + 3, n_plant + 4, n_plant + 5
        f[ip, 3], g[ip, 3] = -a_p, 1.0
        f[iq, 4], g[iq, 4] = -a_p, 1.0
        # r_g' = -(v_g'/V + r_g)/tau_r with v_g' = -a_v v_g + n_v
        f[ir, 5], f[ir, 1], g[ir, 1] = -1.0 / tau_r, a_t[1] / (v * tau_r), -1.0 / (v * tau_r)
        qc += [2.0 * a_p * var_pq, 2.0 * a_p * var_pq]
        acc = [names.SENSORS.index(c) for c in ACCELEROMETERS]
        h[acc, 3:6] = -lin.c[np.ix_(acc, [_P, _Q, _R])] @ t_bl
    return f, g, np.diag(qc), h


def pad_bank(bank, gust_model: str = "dryden_states"):
    """A bank of the plain states (``names.STATES``) as one of ``names.STATES`` + the gust
    states of ``gust_model``, the gust states inert: for every hypothesis filter::

        Phi' = [[Phi, 0], [0, 0]]    B_d' = [[B_d], [0]]    H' = [H, 0]    K' = [[K], [0]]

    and A, the trims, the settings and the flight condition as they were. From x_g = 0 the gust
    states stay 0 (no input, no gain, no coupling), so every residual, A and the probabilities
    are the bank's own; Phi' (I - K' H') has the eigenvalues of Phi (I - K H) and ng zeros.
    What it is for: a scheduled-bank file holds one state count (``cpp/f16mmae/bank_schedule.h``
    checks the nodes' state names), so nodes without gust states join nodes with them padded.
    A bank that already has these states is returned as it is; any other state set is a
    ValueError naming it. The metadata records ``inert_gust_states``."""
    import json

    from .. import core

    states = GUST_STATE_MODELS[gust_model]
    have = tuple(bank.state_names)
    if have == names.STATES + states:
        return bank
    if have != names.STATES:
        raise ValueError(f"pad_bank: the bank's states {', '.join(have)} are not the plain states "
                         f"({names.NX}) or those with the {gust_model} gust states")
    if bank.schedule is not None:
        raise ValueError("pad_bank: a scheduled bank is padded node by node")
    nx, ng = len(have), len(states)

    def rows(m):
        return np.vstack([np.asarray(m), np.zeros((ng, np.asarray(m).shape[1]))])

    hyps = []
    for h in bank.hypotheses:
        phi = np.zeros((nx + ng, nx + ng))
        phi[:nx, :nx] = h.phi
        width, level_q = np.asarray(h.uninformative_width), np.asarray(h.uninformative_level_q)
        hyps.append(core.HypothesisModel(
            name=h.name, phi=phi, bd=rows(h.bd), h=np.hstack([np.asarray(h.h), np.zeros((len(h.h), ng))]),
            k=rows(h.k), a=np.asarray(h.a),
            uninformative_width=width if width.any() else None,
            uninformative_level_q=level_q if level_q.any() else None, dwell_nats=h.dwell_nats))
    meta = json.loads(bank.metadata) if bank.metadata else {}
    meta["inert_gust_states"] = list(states)
    settings = {k: v for k, v in bank.estimator_settings.items() if k in ("p_min", "threshold", "dwell_s")}
    return core.ModelBank(
        hyps, state_names=list(names.STATES + states), input_names=list(bank.input_names),
        measurement_names=list(bank.measurement_names), u_trim=np.asarray(bank.u_trim),
        z_trim=np.asarray(bank.z_trim), h_output=np.hstack([np.asarray(bank.h_output), np.zeros((len(bank.z_trim), ng))]),
        frame_rate_hz=bank.frame_rate_hz, mach=bank.mach, alt_ft=bank.alt_ft, tuning=bank.tuning, **settings,
        metadata=json.dumps(meta, sort_keys=True, separators=(",", ":")))


def pad_state(x: np.ndarray, gust_model: str = "dryden_states") -> np.ndarray:
    """A trim state of ``names.STATES`` with the gust states of ``gust_model`` appended at 0
    (their trim); one that already has them unchanged."""
    x = np.asarray(x, dtype=float)
    full = names.NX + len(GUST_STATE_MODELS[gust_model])
    if len(x) == full:
        return x
    if len(x) != names.NX:
        raise ValueError(f"pad_state: {len(x)} states, neither {names.NX} nor {full}")
    return np.concatenate([x, np.zeros(full - names.NX)])
