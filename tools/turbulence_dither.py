"""The dither at every turbulence level: the gusts' own n_z and rates against the dither's, the
adaptive dither's share of them, and the flaperons' evidence (truth/dither.py ``adaptive_gains``,
``--adaptive-dither``; docs/results/turbulence_banks.md, round 13).

1. ``mix``: the turbulence line's share h the closed loop sets, per level: no-failure flights
   with the turbulence bank set and ``--adaptive-dither`` (tuning seeds of kind
   ``turbulence_dither`` at campaign seed 7), percentiles of h after the first 10 s.
2. ``levels``: at the nominal point (20,000 ft, Mach 0.4; no sensor noise, raw feedback, one
   seed), per level the gusts' own peak and RMS of Delta n_z, q and p (flown without dither),
   and the dither's part (the flight with it minus the one without: the same gusts) for the
   fixed dither and for the adaptive one held at the level's median h: its peak and its peak
   over the gusts' (the criterion: at most ``ADAPTIVE_GUST_SHARE``; the fixed dither in calm air:
   ``CRITERION``).
3. ``evidence``: LF and RF failures (complete at 3 s, 8-s flights as the single campaign's) in
   the set, fixed and adaptive dither: the failed flaperon's log-odds gained after the failure,
   ln(p_f / p_min) (p_min the member's floor) when p_f first reaches 0.9, else at the end (5 s),
   in all and per frame, against the declaration's need ln(0.9 / p_min).
4. ``envelope`` (``--envelope``, alone): severe air at points over the envelope, the turbulence
   line in full (h = 1) against the gusts' own peaks, as part 2 (one adapted bank's rule brings
   it in there; truth/dither.py ``adapted_dither_reference``).
5. ``rudder`` (``--rudder``, alone): moderate and severe air at the same points and at the
   envelope's highest points, the rudder's line at the gain one adapted bank's rule sets there
   (truth/dither.py ``adaptive_rudder_gain`` at the median measured rho-bar of a no-failure
   flight of the scheduled default, after its first 10 s; bounded by ``Dither.rudder_gain_bound``)
   and the flaperons' turbulence line as the rule sets it in that air (moderate h = 0, severe
   h = 1): the whole dither's part of n_y, r and p against the gusts' own peaks, as part 4;
   met where it is at most ``ADAPTIVE_GUST_SHARE`` of them or at most the fixed rudder line's.

    .venv/bin/python tools/turbulence_dither.py --flights 4 --seconds 60
    .venv/bin/python tools/turbulence_dither.py --envelope
    .venv/bin/python tools/turbulence_dither.py --rudder
"""
from __future__ import annotations

import argparse
import dataclasses
import math

import numpy as np

import f16mmae.design.turbulence_banks  # noqa: F401  (registers the set with the bank loader)
from f16mmae.banks import load_bank
from f16mmae.design.turbulence_banks import MEMBER_P_MIN
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import FRAME_RATE_HZ, TURBULENCE_LEVELS
from f16mmae.seeds import evaluation_seed
from f16mmae.truth import FlightControlSystem, Scenario, TruthModel
from f16mmae.truth.dither import (ADAPTIVE_DITHER_REFERENCE, ADAPTIVE_GUST_SHARE, CRITERION, DitherSpec, adaptive_mix,
                                  adaptive_rudder_gain)
from f16mmae.truth.failures import make_failure

#: (name, z index, unit factor) of the channels the criterion reads.
CHANNELS = (("nz_g", 3, 1.0), ("q_deg_s", 2, 180.0 / math.pi), ("p_deg_s", 4, 180.0 / math.pi))
#: Part 5's: the rudder line's (n_y, r, p).
RUDDER_CHANNELS = (("ny_g", 6, 1.0), ("r_deg_s", 5, 180.0 / math.pi), ("p_deg_s", 4, 180.0 / math.pi))


def mix_history(model_bank, level: str, seed: int, seconds: float) -> np.ndarray:
    """h after each frame of one no-failure flight of the set with the adaptive dither."""
    est = Estimator(model_bank, turbulence_banks=True, adaptive_dither=True)
    h: list[float] = []
    fly(Scenario(turbulence=level, duration_s=seconds, seed=seed, feedback="reconfigure"), model_bank,
        estimator=est, on_frame=lambda t, u, z, a: h.append(
            adaptive_mix(est.turbulence_power_ratio, ADAPTIVE_DITHER_REFERENCE[est.turbulence_member])))
    return np.array(h)


def truth_z(level: str, seed: int, seconds: float, dither: bool, h: float, mach: float = 0.4,
            alt_ft: float = 20000.0, rudder_rho: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(z_ideal per frame, trim z) of a truth flight on raw feedback, the dither held at mix h
    (and the rudder's line at ``adaptive_rudder_gain(rudder_rho, its bound)`` when given)."""
    sc = Scenario(mach=mach, alt_ft=alt_ft, duration_s=seconds, noise=False, feedback="raw", turbulence=level,
                  seed=seed, dither=DitherSpec(enabled=dither))
    truth = TruthModel(sc)
    fcs = FlightControlSystem(truth.trim, dither=sc.dither, ari=sc.ari)
    truth.attach(fcs)
    g_rud = 1.0 if rudder_rho is None else adaptive_rudder_gain(rudder_rho, fcs.dither.rudder_gain_bound)
    truth.set_dither_gain(fcs, [1.0, 1.0, 1.0 - h, 1.0 - h, g_rud], [0.0, 0.0, h, h, 0.0])
    truth.fly_frames(int(round(seconds * FRAME_RATE_HZ)))
    truth.detach(fcs)
    truth.close()
    return truth.truth_log["z_ideal"], np.asarray(truth.trim.z)


def levels_table(seed: int, seconds: float, mixes: dict) -> dict:
    """Part 2's table; returns {channel: {"gusts" | "fixed" | "adaptive": [peak per level]}}."""
    peaks = {name: {"gusts": [], "fixed": [], "adaptive": []} for name, _, _ in CHANNELS}
    print(f"\n2. At the nominal point, {seconds:g} s, seed {seed}, no noise, raw feedback: the gusts' peak / RMS, "
          f"the dither's part peak (share of the gusts' peak), fixed and adaptive at the level's median h")
    print("| turbulence | h | " + " | ".join(f"gusts {n} peak / RMS | fixed {n} | adaptive {n}" for n, _, _ in CHANNELS)
          + " | criterion |")
    print("|---|---|" + "---|---|---|" * len(CHANNELS) + "---|")
    for level in TURBULENCE_LEVELS:
        h = float(mixes.get(level, 0.0))
        z0, trim = truth_z(level, seed, seconds, False, 0.0)
        z1, _ = truth_z(level, seed, seconds, True, 0.0)
        z2, _ = truth_z(level, seed, seconds, True, h)
        cells, ok = [], True
        for name, j, k in CHANNELS:
            gust = (z0[:, j] - trim[j]) * k
            gp, gr = float(np.abs(gust).max()), float(np.sqrt(np.mean(gust ** 2)))
            d1 = float(np.abs(z1[:, j] - z0[:, j]).max() * k)
            d2 = float(np.abs(z2[:, j] - z0[:, j]).max() * k)
            calm = CRITERION["nz_g"] if name == "nz_g" else CRITERION["rate_deg_s"]
            ok &= d2 <= max(calm if h == 0.0 else 0.0, ADAPTIVE_GUST_SHARE * gp)
            share = lambda d: f"{d:.3f} ({d / gp:.2f})" if gp > 0.1 * calm else f"{d:.3f}"
            cells.append(f"{gp:.3f} / {gr:.3f} | {share(d1)} | {share(d2)}")
            for key, v in (("gusts", gp), ("fixed", d1), ("adaptive", d2)):
                peaks[name][key].append(v)
        print(f"| {level} | {h:.2f} | " + " | ".join(cells) + f" | {'met' if ok else 'NOT met'} |", flush=True)
    return peaks


#: Part 4's flight conditions (Mach, ft): the envelope's corners, the nominal point and two between.
ENVELOPE_POINTS = ((0.3, 5000.0), (0.8, 5000.0), (0.4, 20000.0), (0.6, 15000.0), (0.4, 35000.0), (0.8, 35000.0),
                   (0.35, 25000.0), (0.7, 30000.0))


def envelope_table(seed: int, seconds: float) -> None:
    """Part 4: over the envelope in severe air, the turbulence line in full (h = 1, as one adapted
    bank's rule sets it there: truth/dither.py adapted_dither_reference) against the gusts' own peaks."""
    print(f"4. Severe air over the envelope, {seconds:g} s, seed {seed}, no noise, raw feedback: the gusts' "
          f"peak, the adaptive dither's part at h = 1 (its share of the gusts' peak; criterion "
          f"<= {ADAPTIVE_GUST_SHARE:g})")
    print("| Mach | altitude, ft | " + " | ".join(f"gusts {n} | dither {n}" for n, _, _ in CHANNELS) + " | criterion |")
    print("|---|---|" + "---|---|" * len(CHANNELS) + "---|")
    for mach, alt in ENVELOPE_POINTS:
        z0, trim = truth_z("severe", seed, seconds, False, 0.0, mach, alt)
        z2, _ = truth_z("severe", seed, seconds, True, 1.0, mach, alt)
        cells, ok = [], True
        for name, j, k in CHANNELS:
            gp = float(np.abs((z0[:, j] - trim[j]) * k).max())
            d2 = float(np.abs(z2[:, j] - z0[:, j]).max() * k)
            ok &= d2 <= ADAPTIVE_GUST_SHARE * gp
            cells.append(f"{gp:.3f} | {d2:.3f} ({d2 / gp:.2f})")
        print(f"| {mach:g} | {alt:g} | " + " | ".join(cells) + f" | {'met' if ok else 'NOT met'} |", flush=True)


#: Part 5's flight conditions (Mach, ft): part 4's and the envelope's highest, where the rudder's
#: line is scheduled smallest against the gusts (the random envelope points R29 and R40).
RUDDER_POINTS = ENVELOPE_POINTS + ((0.66, 32909.0), (0.8, 33757.0))


def median_rho_bar(model_bank, level: str, seed: int, seconds: float, mach: float, alt_ft: float) -> float:
    """The measured rho-bar's median after the first 10 s of one no-failure flight of the
    scheduled default (its adaptive dither in the loop)."""
    est = Estimator(model_bank, adapt_turbulence=True)
    rho: list[float] = []
    fly(Scenario(mach=mach, alt_ft=alt_ft, turbulence=level, duration_s=seconds, seed=seed), model_bank,
        estimator=est, on_frame=lambda t, u, z, a: rho.append(est.measured_power_ratio))
    return float(np.median(rho[int(10 * FRAME_RATE_HZ):]))


def rudder_table(seed: int, seconds: float, truth_seconds: float) -> None:
    """Part 5: the rudder's line at its rough-air gain against the gusts' own peaks."""
    _, _, bank = load_bank("scheduled")
    print(f"5. Moderate and severe air, {truth_seconds:g} s, seed {seed}, no noise, raw feedback: the gusts' peak, "
          f"the dither's part with the rudder's line at its rough-air gain g (at the median rho-bar of a "
          f"{seconds:g}-s flight; G its bound) and the fixed one's (g = 1), their shares of the gusts' peak "
          f"(criterion: <= {ADAPTIVE_GUST_SHARE:g}, or no more than the fixed line's); the flaperons' turbulence "
          f"line h = 0 in moderate air, 1 in severe")
    print("| level | Mach | altitude, ft | rho-bar | g (G) | "
          + " | ".join(f"gusts {n} | fixed {n} | adaptive {n}" for n, _, _ in RUDDER_CHANNELS) + " | criterion |")
    print("|---|---|---|---|---|" + "---|---|---|" * len(RUDDER_CHANNELS) + "---|")
    for level, h in (("moderate", 0.0), ("severe", 1.0)):
        for mach, alt in RUDDER_POINTS:
            sc = Scenario(mach=mach, alt_ft=alt)
            truth = TruthModel(sc)
            bound = FlightControlSystem(truth.trim, dither=sc.dither).dither.rudder_gain_bound
            truth.close()
            rho = median_rho_bar(bank, level, seed, seconds, mach, alt)
            z0, trim = truth_z(level, seed, truth_seconds, False, 0.0, mach, alt)
            z1, _ = truth_z(level, seed, truth_seconds, True, h, mach, alt)
            z2, _ = truth_z(level, seed, truth_seconds, True, h, mach, alt, rudder_rho=rho)
            cells, ok = [], True
            for name, j, k in RUDDER_CHANNELS:
                gp = float(np.abs((z0[:, j] - trim[j]) * k).max())
                d1 = float(np.abs(z1[:, j] - z0[:, j]).max() * k)
                d2 = float(np.abs(z2[:, j] - z0[:, j]).max() * k)
                ok &= d2 <= max(ADAPTIVE_GUST_SHARE * gp, d1)
                cells.append(f"{gp:.3f} | {d1:.3f} ({d1 / gp:.2f}) | {d2:.3f} ({d2 / gp:.2f})")
            print(f"| {level} | {mach:g} | {alt:g} | {rho:.2f} | {adaptive_rudder_gain(rho, bound):.2f} ({bound:.2f}) | "
                  + " | ".join(cells) + f" | {'met' if ok else 'NOT met'} |", flush=True)


def figure(peaks: dict, path: str) -> None:
    """Part 2's peaks per level: the gusts', the fixed and the adaptive dither's, per channel."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(CHANNELS), figsize=(12, 3.6))
    x = np.arange(len(TURBULENCE_LEVELS))
    for ax, (name, _, _) in zip(axes, CHANNELS):
        for k, (key, label) in enumerate((("gusts", "gusts"), ("fixed", "fixed dither"), ("adaptive", "adaptive dither"))):
            ax.bar(x + (k - 1) * 0.27, peaks[name][key], 0.27, label=label)
        ax.plot(x, ADAPTIVE_GUST_SHARE * np.array(peaks[name]["gusts"]), "k_", markersize=18,
                label=f"{ADAPTIVE_GUST_SHARE:g} x gusts")
        ax.set_xticks(x, TURBULENCE_LEVELS)
        ax.set_title(f"peak {name}")
    axes[0].legend(fontsize=8)
    fig.suptitle("Nominal point: the gusts' peak response and the dither's part, per level")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def evidence_table(model_bank, flights: int) -> None:
    p_min = MEMBER_P_MIN[1]
    need = math.log(0.9 / p_min)
    print(f"\n3. Flaperon evidence in severe turbulence (8-s flights, failure at 3 s, tuning seeds of kind "
          f"turbulence_dither_evidence at campaign seed 7, {flights} per case): ln(p_f / p_min) when p_f first "
          f"reaches 0.9, else at the end (5 s = 320 frames after the failure), and per frame since the failure; "
          f"the declaration needs ln(0.9 / p_min) = {need:.1f}")
    print("| dither | case | median (min-max) nats | median (min-max) nats per frame | declared f |")
    print("|---|---|---|---|---|")
    for adaptive in (False, True):
        for case in ("LF", "RF"):
            ev, rate, hits = [], [], 0
            for n in range(flights):
                seed = evaluation_seed("turbulence_dither_evidence", 7, case, n)
                sc = Scenario(turbulence="severe", duration_s=8.0, seed=seed, feedback="reconfigure",
                              failures=(make_failure(case, 3.0),))
                opts = {"turbulence_banks": True, **({} if adaptive else {"fixed_dither": True})}
                r = fly(sc, model_bank, estimator_options=opts)
                after = r.probabilities[int(3.0 * FRAME_RATE_HZ):, list(r.hypotheses).index(case)]
                after = np.nan_to_num(after, nan=1.0)   # off line: the bank went to level 1 on it
                hit = np.flatnonzero(after >= 0.9)
                end = int(hit[0]) if hit.size else len(after) - 1
                ev.append(math.log(max(after[end], p_min) / p_min))
                rate.append(ev[-1] / (end + 1))
                hits += r.final_hypothesis == case
            ev, rate = np.array(ev), np.array(rate)
            print(f"| {'adaptive' if adaptive else 'fixed'} | {case} | {np.median(ev):.1f} ({ev.min():.1f}-{ev.max():.1f}) | "
                  f"{np.median(rate):.3f} ({rate.min():.3f}-{rate.max():.3f}) | {hits}/{flights} |", flush=True)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--flights", type=int, default=4, help="no-failure flights per level (part 1)")
    p.add_argument("--seconds", type=float, default=60.0, help="their length, s")
    p.add_argument("--truth-seconds", type=float, default=30.0, help="the truth flights' length (part 2), s")
    p.add_argument("--evidence-flights", type=int, default=10, help="failure flights per case (part 3; 0: skip)")
    p.add_argument("--figure", default=None, metavar="PNG", help="part 2's peaks as a figure")
    p.add_argument("--envelope", action="store_true", help="part 4 only: severe air over the envelope")
    p.add_argument("--rudder", action="store_true",
                   help="part 5 only: the rudder's line at its rough-air gain's bound over the envelope")
    args = p.parse_args(argv)
    if args.envelope:
        envelope_table(7, args.truth_seconds)
        return 0
    if args.rudder:
        rudder_table(7, args.seconds, args.truth_seconds)
        return 0
    _, _, bank = load_bank("turbulence")
    print("1. The turbulence line's share h the closed loop sets (no failure; percentiles 5/50/95 after 10 s)")
    print("| turbulence | h 5 / 50 / 95 % |")
    print("|---|---|")
    mixes = {}
    for level in TURBULENCE_LEVELS:
        h = np.concatenate([mix_history(bank, level, evaluation_seed("turbulence_dither", 7, level, n), args.seconds)
                            [int(10 * FRAME_RATE_HZ):] for n in range(args.flights)])
        q = np.percentile(h, [5, 50, 95])
        mixes[level] = q[1]
        print(f"| {level} | {q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} |", flush=True)
    peaks = levels_table(7, args.truth_seconds, mixes)
    if args.figure:
        figure(peaks, args.figure)
    if args.evidence_flights:
        evidence_table(bank, args.evidence_flights)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
