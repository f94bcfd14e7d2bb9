"""Can a subliminal excitation isolate a complete VEL or AOA failure in calm air?  (issue 13
item 4: the physics, measured before the excitation is built.)

A ``complete`` VEL or AOA failure reads the trim value plus noise.  In calm air the aircraft
stays at trim but for the dither, so the failure shows only through how far the dither moves
forward speed u and angle of attack alpha against the sensor noise (VEL 0.5 ft/s, AOA 0.1 deg).
The surface dither moves u by about 0.2 ft/s peak (stabilators at 1.7 Hz).  The candidate here
is a throttle dither, a sinusoid on ``fcs/throttle-cmd-norm`` about its trim::

    th(t) = a_th sin(2 pi f_th t)        (throttle command, 0..1; trim about 0.246)

Throttle column.  JSBSim's own ``FGLinearization`` of the derived aircraft (its first input,
``ThtlCmd``) gives ``b_th`` (8,), ``x_a' = A x_a + B d + b_th th``: about +26.9 ft/s^2 of u'
per unit command at the nominal point (thrust along the body x axis, 17,300 lbf per unit
command), small alpha' and q' from the thrust line.  The JSBSim turbine engine reaches its new
thrust within one frame for these steps (no spool lag is visible, ``jsbsim_response``), so the
column is a direct input, no engine state.  Then ``Delta n_x = b_th[0] th / g`` at the instant
of the change, and the amplitude for a peak ``Delta n_x`` of ``n`` g is
``a_th = n g / b_th[0]`` (``throttle_amplitude``).

Criterion (subliminal to the pilot): peak ``|Delta n_x| <= 0.02 g``, the project's lateral
criterion (``truth.dither.CRITERION["ny_g"]``).  Laboratory thresholds of whole-body linear
acceleration are about the same along the x and y axes and larger along z (Benson, Spencer and
Stott, Aviat. Space Environ. Med. 57, 1986: about 6 cm/s^2 in x and y); the project's n_z and
n_y criteria (0.05 g, 0.02 g) keep that ratio, so the x axis gets the y axis's 0.02 g.

Evidence.  ``design.distinguish`` gives the expected evidence per frame ``D(T, F)`` that the
bank gathers for the true hypothesis T against a competitor F; here with a sixth input:
every filter and the truth get the discrete throttle column ``Bd_th`` (the throttle is known
to the estimator, it is not a failure hypothesis), and the truth flies in CLOSED loop with
the project's FCS (``truth.fcs.FlightControlSystem.linear_model``, forward Euler at the frame
rate, fed the healthy noise-free measurements ``H x``: the FCS uses neither the AOA reading
nor, but for weak saturated terms, the VEL reading).  The noise-free closed-loop response gives
the total inputs ``u`` (FCS + dither) and the throttle; ``distinguish.rates`` replays them open
loop, which reproduces the closed-loop states exactly.  Calm air only: the stochastic part is
the sensor noise through the filters (the noise the FCS feeds back into the states is left
out); in turbulence the closed-loop gust response matters and campaigns measure it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import names
from . import distinguish as ds
from .bank import BankDesign
from .discretize import zoh
from .linearize import throttle_column

#: Standard gravity (ft/s^2).
G_FPS2 = 32.174
#: Throttle property of the derived aircraft (0..1; the mixer doubles it to throttle-pos-norm).
THROTTLE_PROPERTY = "fcs/throttle-cmd-norm"
#: Subliminal criterion on the throttle dither (peak |Delta n_x|, g); see the docstring.
CRITERION_NX_G = 0.02


def throttle_amplitude(nx_peak_g: float, column: np.ndarray) -> float:
    """Throttle amplitude (command units) whose direct effect is a peak ``Delta n_x`` of
    ``nx_peak_g`` (g): ``n g / b_th[0]``."""
    return float(nx_peak_g) * G_FPS2 / float(column[0])


def discrete_throttle_column(design: BankDesign, column: np.ndarray) -> np.ndarray:
    """(13, 1) ``Bd_th``: the column through the design model's ``F`` under the frame's
    zero-order hold (the lag states get nothing)."""
    b = np.zeros((names.NX, 1))
    b[:len(column), 0] = column
    return zoh(design.continuous.f, b, 1.0 / design.frame_rate_hz)[1]


@dataclass(frozen=True)
class ClosedLoop:
    """The noise-free closed-loop linear response: ``u`` (frames, 6) the five surface
    commands (FCS + dither, perturbations) and the throttle; ``x`` (frames, 13) the truth
    states (perturbations), u in ft/s, alpha in rad (``names.STATES``)."""

    u: np.ndarray
    x: np.ndarray


def closed_loop(design: BankDesign, fcs, bd_truth: np.ndarray, dither: np.ndarray,
                throttle: np.ndarray) -> ClosedLoop:
    """Fly the design model in closed loop with ``fcs`` (a FlightControlSystem at the design's
    trim; its ``linear_model``, forward Euler): ``dither`` (frames, 5) rad and ``throttle``
    (frames,) added to the commands; ``bd_truth`` (13, 6) the truth's input matrix."""
    ac, bc, cc, dc = fcs.linear_model()
    dt = 1.0 / design.frame_rate_hz
    phi, h = design.discrete.phi, design.continuous.h
    x, xc = np.zeros(names.NX), np.zeros(ac.shape[0])
    us, xs = np.zeros((len(dither), 6)), np.zeros((len(dither), names.NX))
    for i in range(len(dither)):
        z = h @ x
        us[i, :5] = cc @ xc + dc @ z + dither[i]
        us[i, 5] = throttle[i]
        xs[i] = x
        xc = xc + dt * (ac @ xc + bc @ z)
        x = phi @ x + bd_truth @ us[i]
    return ClosedLoop(u=us, x=xs)


def _with_throttle(f: ds.ScoredFilter, bd_th: np.ndarray) -> ds.ScoredFilter:
    return ds.ScoredFilter(phi=f.phi, bd=np.hstack([f.bd, bd_th]), h=f.h, k=f.k, a_inv=f.a_inv,
                           c=f.c, levels=f.levels)


def evidence(design: BankDesign, fcs, column: np.ndarray, truth: str, competitors: list[str],
             nx_peak_g: float, frequency_hz: float, seconds: float = 40.0) -> tuple[dict[str, float], ClosedLoop]:
    """Calm-air ``D(truth, F)`` (nats per frame) for every competitor F named, with the surface
    dither and a throttle dither of peak direct ``Delta n_x`` ``nx_peak_g`` at ``frequency_hz``
    (0 g: no throttle dither), and the closed-loop response it came from (module docstring)."""
    bd_th = discrete_throttle_column(design, column)
    bd_t, h_t = ds.truth_matrices(design, truth)
    bd_t = np.hstack([bd_t, bd_th])
    frames = int(seconds * design.frame_rate_hz)
    t = np.arange(frames) / design.frame_rate_hz
    th = throttle_amplitude(nx_peak_g, column) * np.sin(2.0 * np.pi * frequency_hz * t)
    loop = closed_loop(design, fcs, bd_t, ds.dither_inputs(frames, design.frame_rate_hz), th)
    own = _with_throttle(ds.scored_filter(design, truth), bd_th)
    comps = [_with_throttle(ds.scored_filter(design, c), bd_th) for c in competitors]
    d = ds.rates(design.discrete.phi, np.zeros_like(design.discrete.qd), design.r, bd_t, h_t,
                 own, comps, loop.u)
    return dict(zip(competitors, d)), loop


@dataclass(frozen=True)
class JsbsimResponse:
    """Peaks over the last half of a JSBSim flight with the surfaces held at trim and a
    throttle sinusoid: |Delta n_x| (g), |Delta u| (ft/s, air-relative), |Delta alpha| (rad);
    and the same from the linear airframe with ``throttle_column`` (open loop)."""

    nx_peak_g: float
    u_peak_fps: float
    alpha_peak_rad: float
    linear_u_peak_fps: float
    linear_alpha_peak_rad: float


def jsbsim_response(fdm, trim, amplitude: float, frequency_hz: float, seconds: float,
                    column: np.ndarray, a_airframe: np.ndarray, sim_rate_hz: float) -> JsbsimResponse:
    """Fly the trimmed derived aircraft ``fdm`` (``aircraft.trimmed_fdm``; surfaces held at the
    trim, no turbulence) with the throttle sinusoid, and the open-loop linear airframe
    ``x' = A x + b_th th`` alongside it (``scipy.signal.lsim``, the throttle held between the
    simulation steps); the peaks are over the last half of the ``seconds``."""
    from scipy.signal import lsim

    n = int(round(seconds * sim_rate_hz))
    w = fdm["inertia/weight-lbs"]
    nx0 = fdm["forces/fbx-total-lbs"] / w
    t = np.arange(1, n + 1) / sim_rate_hz
    th = amplitude * np.sin(2.0 * np.pi * frequency_hz * (t - 1.0 / sim_rate_hz))
    rec = np.zeros((n, 3))
    for i in range(n):
        fdm[THROTTLE_PROPERTY] = trim.throttle + th[i]
        fdm.run()
        rec[i] = (fdm["forces/fbx-total-lbs"] / w - nx0, fdm["velocities/u-aero-fps"] - trim.z[0],
                  fdm["aero/alpha-rad"] - trim.alpha_rad)
    fdm[THROTTLE_PROPERTY] = trim.throttle
    lin = lsim((a_airframe, column[:, None], np.eye(len(column)), np.zeros((len(column), 1))),
               th, t - t[0])[2]
    half = slice(n // 2, n)
    return JsbsimResponse(nx_peak_g=float(np.abs(rec[half, 0]).max()),
                          u_peak_fps=float(np.abs(rec[half, 1]).max()),
                          alpha_peak_rad=float(np.abs(rec[half, 2]).max()),
                          linear_u_peak_fps=float(np.abs(lin[half, 0]).max()),
                          linear_alpha_peak_rad=float(np.abs(lin[half, 1]).max()))


#: Channels of :func:`throttle_dither_peaks`: name, scale to the printed unit.
PEAK_CHANNELS: tuple[tuple[str, float], ...] = (
    ("nx_g", 1.0), ("nz_g", 1.0), ("q_deg_s", 180.0 / np.pi), ("u_fps", 1.0), ("alpha_deg", 180.0 / np.pi))


def _fly_recording_nx(scenario) -> np.ndarray:
    """(frames + 1, 5) n_x (g), n_z (g), q, u, alpha of a raw-feedback flight of ``scenario`` on
    the python truth engine (which exposes its aircraft), read after every frame."""
    from ..names import FRAME_RATE_HZ
    from ..truth import FlightControlSystem, TruthModel

    truth = TruthModel(scenario, engine="python")
    fcs = FlightControlSystem(truth.trim, scenario)
    fdm = truth.fdm
    n = int(round(scenario.duration_s * FRAME_RATE_HZ))
    rows = np.zeros((n + 1, 5))
    for i in range(n + 1):
        z = truth.measure()
        w = fdm["inertia/weight-lbs"]
        rows[i] = (fdm["forces/fbx-total-lbs"] / w, z[3], z[2], fdm["velocities/u-aero-fps"], z[1])
        if i < n:
            truth.advance(fcs.command(z, i / FRAME_RATE_HZ))
    truth.close()
    return rows


def throttle_dither_peaks(spec, level: str, seed: int = 1, duration_s: float = 30.0, mach: float = 0.4,
                          alt_ft: float = 20_000.0) -> dict:
    """The throttle dither's peak closed-loop response in turbulence ``level`` beside the
    gusts' own: one flight with the throttle dither of ``spec`` (a DitherSpec) and one with
    the same surface dither but no throttle dither (same seed: the same gusts; no sensor noise,
    FCS on raw sensors, at ``mach``, ``alt_ft``).  ``dither``: peak |with - without| per
    ``PEAK_CHANNELS`` (the throttle's part, the closed loop being close to linear); ``gusts``:
    peak |without - its first frame| (the rest: the gusts' and the surface dither's)."""
    import dataclasses

    from ..truth import Scenario

    runs = [_fly_recording_nx(Scenario(mach=mach, alt_ft=alt_ft, duration_s=duration_s, noise=False, feedback="raw",
                                       turbulence=level, seed=seed, dither=d))
            for d in (spec, dataclasses.replace(spec, throttle_amplitude=0.0, throttle_schedule=False))]
    d = np.abs(runs[0] - runs[1]).max(axis=0)
    g = np.abs(runs[1] - runs[1][0]).max(axis=0)
    return {"dither": {name: float(d[j] * k) for j, (name, k) in enumerate(PEAK_CHANNELS)},
            "gusts": {name: float(g[j] * k) for j, (name, k) in enumerate(PEAK_CHANNELS)}}


#: Throttle dither frequencies (Hz) and peaks (g) the table scans.
SCAN_FREQUENCY_HZ: tuple[float, ...] = (0.1, 0.2, 0.3, 0.5, 1.0)
SCAN_NX_G: tuple[float, ...] = (0.01, 0.02, 0.05)


def ideal_rate(x: np.ndarray, sensor: str) -> float:
    """Upper bound of the evidence per frame (nats) for a complete failure of ``sensor`` (VEL or
    AOA) against no failure, for the closed-loop states ``x`` (frames, 13): a detector that knew
    the aircraft's state exactly would gather ``mean(dz^2) / (2 sigma^2)``, dz the sensor's
    true excursion from trim (u or alpha: the air-relative states of the design model) and
    sigma its noise (``truth.sensors.NOISE_SIGMA``)."""
    from ..truth.sensors import NOISE_SIGMA

    j = names.SENSORS.index(sensor)
    col = {"VEL": 0, "AOA": 1}[sensor]
    return float(np.mean(x[:, col] ** 2) / (2.0 * NOISE_SIGMA[j] ** 2))


#: Turbulence levels and throttle dither frequencies (Hz) of the peaks table.
PEAK_LEVELS: tuple[str, ...] = ("none", "light", "moderate")
PEAK_FREQUENCY_HZ: tuple[float, ...] = (0.1, 0.2)
#: Throttle dither amplitude of the peaks table (command units): CRITERION_NX_G at the nominal
#: point (``throttle_amplitude(CRITERION_NX_G, throttle_column(...))`` = 0.0239).
PEAK_AMPLITUDE = 0.0239


def thrust_table(decimals: int = 3) -> list[list[float]]:
    """``b_x`` (ft/s^2 per unit throttle command, u' of ``throttle_column``) at the level trim of
    every point of ``truth.dither.THROTTLE_GRID_MACH`` x ``THROTTLE_GRID_ALT_FT``, rounded to
    ``decimals``: the table ``truth.dither.THRUST_ACCEL_FPS2``.  A point that does not trim
    (slow and high) takes the value of the nearest faster Mach at its altitude."""
    from ..truth import aircraft
    from ..truth.dither import THROTTLE_GRID_ALT_FT, THROTTLE_GRID_MACH

    rows: list[list[float | None]] = []
    for m in THROTTLE_GRID_MACH:
        row: list[float | None] = []
        for h in THROTTLE_GRID_ALT_FT:
            try:
                fdm, _ = aircraft.trimmed_fdm(mach=m, alt_ft=h)
            except aircraft.TrimError:
                row.append(None)
                continue
            row.append(round(float(throttle_column(fdm)[0]), decimals))
        rows.append(row)
    for j in range(len(THROTTLE_GRID_ALT_FT)):
        for i in reversed(range(len(rows) - 1)):
            if rows[i][j] is None:
                rows[i][j] = rows[i + 1][j]
    if any(v is None for r in rows for v in r):
        raise RuntimeError("the thrust table has a column that trims at no Mach of the grid")
    return rows


#: Flight conditions (Mach, ft) of the envelope peaks table: the nominal point and the corners.
ENVELOPE_POINTS: tuple[tuple[float, float], ...] = ((0.4, 20_000.0), (0.8, 5_000.0), (0.45, 35_000.0),
                                                    (0.3, 5_000.0), (0.8, 35_000.0))


def _print_envelope_peaks() -> int:
    """The scheduled throttle dither's calm-air peaks at ``ENVELOPE_POINTS`` (20-s flights, 0.1 Hz)."""
    from ..truth.dither import SCHEDULED_THROTTLE_FREQUENCY_HZ, DitherSpec, scheduled_throttle_amplitude

    spec = DitherSpec(throttle_schedule=True, throttle_frequency_hz=SCHEDULED_THROTTLE_FREQUENCY_HZ)
    print("| Mach / alt (ft) | scheduled a_th | peak dn_x (g) | peak dn_z (g) | peak q (deg/s) | peak du (ft/s) |")
    print("|---|---|---|---|---|---|")
    for mach, alt in ENVELOPE_POINTS:
        r = throttle_dither_peaks(spec, "none", duration_s=20.0, mach=mach, alt_ft=alt)["dither"]
        print(f"| {mach:g} / {alt:,.0f} | {scheduled_throttle_amplitude(mach, alt):.4f} | {r['nx_g']:.3f} | "
              f"{r['nz_g']:.3f} | {r['q_deg_s']:.2f} | {r['u_fps']:.2f} |", flush=True)
    return 0


def _print_peaks() -> int:
    from ..truth.dither import DitherSpec

    print("| level | f (Hz) | " + " | ".join(f"throttle's {n} | rest's {n}" for n, _ in PEAK_CHANNELS) + " |")
    print("|---|---|" + "---|---|" * len(PEAK_CHANNELS))
    for level in PEAK_LEVELS:
        for f_hz in PEAK_FREQUENCY_HZ:
            r = throttle_dither_peaks(DitherSpec(throttle_amplitude=PEAK_AMPLITUDE, throttle_frequency_hz=f_hz), level)
            cells = " | ".join(f"{r['dither'][n]:.3f} | {r['gusts'][n]:.3f}" for n, _ in PEAK_CHANNELS)
            print(f"| {level} | {f_hz:g} | {cells} |")
    return 0


def main(argv: list[str] | None = None) -> int:
    """``python -m f16mmae.design.excitation [--tuning tuned]``: the tables of
    docs/results/excitation.md (JSBSim against the linear column; calm-air evidence of a
    complete VEL and AOA failure against every other single hypothesis, for the bank designed
    for light turbulence, the same tuning designed for calm air, and the calm-air exact model
    (the untuned design: no pseudonoise)) as Markdown; ``--peaks``: the throttle dither's
    closed-loop peaks per turbulence level."""
    import argparse
    import dataclasses

    from ..names import SIM_RATE_HZ, SINGLE_HYPOTHESES
    from ..truth import aircraft
    from ..truth.fcs import FlightControlSystem
    from .bank import design_bank
    from .tuning import load_tuning

    p = argparse.ArgumentParser(description=main.__doc__)
    p.add_argument("--tuning", default="tuned")
    p.add_argument("--failure-model", default=None, choices=("complete", "cover"),
                   help="the tuning's failure model unless given")
    p.add_argument("--peaks", action="store_true",
                   help="print only the throttle dither's closed-loop JSBSim peaks per turbulence level")
    p.add_argument("--envelope-peaks", action="store_true",
                   help="print only the scheduled throttle dither's calm-air peaks over the envelope")
    p.add_argument("--thrust-table", action="store_true",
                   help="print only truth.dither.THRUST_ACCEL_FPS2 (the throttle schedule's table)")
    args = p.parse_args(argv)
    if args.peaks:
        return _print_peaks()
    if args.envelope_peaks:
        return _print_envelope_peaks()
    if args.thrust_table:
        print("(" + ",\n ".join("(" + ", ".join(f"{v:g}" for v in r) + ")" for r in thrust_table()) + ")")
        return 0
    tuning = load_tuning(args.tuning)
    if args.failure_model:
        tuning = dataclasses.replace(tuning, failure_model=args.failure_model)
    exact = dataclasses.replace(load_tuning("untuned"), failure_model=tuning.failure_model, turbulence="none")
    designs = {"light": design_bank(tuning=dataclasses.replace(tuning, turbulence="light")),
               "none": design_bank(tuning=dataclasses.replace(tuning, turbulence="none")),
               "exact": design_bank(tuning=exact)}
    design = designs["light"]
    fdm, trim = aircraft.trimmed_fdm(mach=design.mach, alt_ft=design.alt_ft)
    column = throttle_column(fdm)
    amp = throttle_amplitude(CRITERION_NX_G, column)
    print(f"tuning {tuning.name}, failure model {tuning.failure_model}; throttle column b_th (per unit command): u' {column[0]:.3f} ft/s^2, "
          f"alpha' {column[1]:.5f} rad/s, q' {column[2]:.5f} rad/s^2; trim throttle {trim.throttle:.4f}; "
          f"a_th for {CRITERION_NX_G} g: {amp:.4f}\n")
    print("| f (Hz) | a_th | JSBSim peak dn_x (g) | JSBSim peak du (ft/s) | linear du | "
          "JSBSim peak dalpha (deg) | linear dalpha |")
    print("|---|---|---|---|---|---|---|")
    for f_hz in SCAN_FREQUENCY_HZ:
        fresh, _ = aircraft.trimmed_fdm(mach=design.mach, alt_ft=design.alt_ft)  # FGLinearization holds its fdm
        r = jsbsim_response(fresh, trim, amp, f_hz, 4.0 / f_hz, column, design.linearized.lin.a, SIM_RATE_HZ)
        print(f"| {f_hz:g} | {amp:.4f} | {r.nx_peak_g:.4f} | {r.u_peak_fps:.3f} | {r.linear_u_peak_fps:.3f} | "
              f"{np.degrees(r.alpha_peak_rad):.4f} | {np.degrees(r.linear_alpha_peak_rad):.4f} |")
    fcs = FlightControlSystem(trim)
    p_min = tuning.estimator.get("p_min", 1e-3)
    print(f"\np_min {p_min:g}: ln(1/p_min) = {np.log(1 / p_min):.1f} nats to lift a hypothesis from the floor")
    print("\n| truth | peak dn_x (g) | f (Hz) | peak du (ft/s) | peak dalpha (deg) | ideal D | "
          "D, light bank (weakest) | D, calm bank (weakest) | calm bank: s to lift | D, calm exact model |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for truth in ("VEL", "AOA"):
        comps = [h for h in SINGLE_HYPOTHESES if h != truth]
        for nx, f_hz in [(0.0, 0.0)] + [(n, f) for n in SCAN_NX_G for f in SCAN_FREQUENCY_HZ]:
            cells = []
            for lv in ("light", "none", "exact"):
                d, loop = evidence(designs[lv], fcs, column, truth, comps, nx, f_hz if nx else 1.0)
                weakest = min(d, key=d.get)
                cells.append(f"{d[weakest]:.3g} ({weakest})")
                if lv == "none":
                    secs = ds.frames_to_lift(d[weakest], p_min) / design.frame_rate_hz
            half = loop.x[len(loop.x) // 2:]
            print(f"| {truth} | {nx:g} | {f_hz:g} | {np.abs(half[:, 0]).max():.3f} | "
                  f"{np.degrees(np.abs(half[:, 1]).max()):.3f} | {ideal_rate(half, truth):.3g} | "
                  f"{cells[0]} | {cells[1]} | {'never' if secs == float('inf') else f'{secs:.2f}'} | {cells[2]} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
