"""The physics' floor under the detection latency, per single failure (issue 13).

Lorden (1971): among sequential detectors of a change from density f_0 to f_1 whose mean run
length to a false alarm is at least gamma frames, the worst-case mean delay is at least

    delay >= ln(gamma) / lambda  frames   (gamma -> infinity),

lambda = D(f_1 || f_0) the Kullback-Leibler rate in nats a frame. CUSUM attains it. For the
bank, f_0 is NONE's residual density and f_1 the failure's: lambda = D(T, NONE), the expected
evidence per frame of ``design/distinguish.py evidence_rates`` (the design's own models, light
air -- the design's Q_d --, the nominal point Mach 0.4 / 20,000 ft, the dither on, open loop).
Isolating T also needs evidence against every other failure; with the weakest competitor W,
lambda_W = min_F D(T, F) bounds the isolation part the same way at that competitor's
false-isolation rate (Nikiforov 1995: the delay of detection-isolation is at least
ln(gamma) / min_F D(T, F), F over NONE and the other failures, when false isolations must be
as rare as false alarms).

gamma from the false-alarm goal: no false declaration in H hours with probability at least
q among the 12 failure hypotheses, each a detector with false alarms at exponential intervals
of mean gamma frames:

    exp(-12 N / gamma) >= q,   N = H * 3600 * 64 frames   =>   ln(gamma) = ln(12 N / -ln q).

H = 10, q = 0.5: ln(gamma) = 17.5 nats; q = 0.95: 20.1 nats.

    .venv/bin/python tools/latency/lorden_bound.py [--design tuned] [--hours 10]

prints a markdown table: per failure lambda against NONE, the weakest competitor and lambda
against it, and the Lorden delays (s) at the two gammas against NONE and against the weakest.
"""
from __future__ import annotations

import argparse
import math

from f16mmae import names
from f16mmae.design.bank import design_bank
from f16mmae.design.distinguish import evidence_rates
from f16mmae.design.model import linearize_truth
from f16mmae.design.tuning import load_tuning


def log_gamma(hours: float, q: float, detectors: int = 12, rate_hz: float = names.FRAME_RATE_HZ) -> float:
    """ln(gamma) for no false alarm in ``hours`` with probability ``q`` among ``detectors``."""
    frames = hours * 3600.0 * rate_hz
    return math.log(detectors * frames / -math.log(q))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--design", default="tuned", help="tuning name (design/tunings; default tuned, the shipped bank)")
    p.add_argument("--hours", type=float, default=10.0, help="the false-alarm horizon H (default 10 h)")
    a = p.parse_args()
    rate = names.FRAME_RATE_HZ
    g50, g95 = log_gamma(a.hours, 0.5), log_gamma(a.hours, 0.95)
    lin = linearize_truth(0.4, 20_000.0)
    d = design_bank(tuning=load_tuning(a.design), linearized=lin, hypotheses=names.SINGLE_HYPOTHESES)
    singles = names.SINGLE_HYPOTHESES[1:]
    print(f"ln(gamma): {g50:.1f} nats (q 0.5), {g95:.1f} nats (q 0.95); {a.hours:g} h, 12 hypotheses, {rate:g} Hz")
    print()
    print("| failure | lambda vs NONE | weakest | lambda vs weakest | Lorden vs NONE, q 0.5 / 0.95 (s) "
          "| vs weakest, q 0.5 / 0.95 (s) |")
    print("|---|---|---|---|---|---|")
    for t in singles:
        competitors = [c for c in names.SINGLE_HYPOTHESES if c != t]
        r = evidence_rates(d, t, competitors)
        weakest = min(competitors, key=lambda c: r[c])
        ln0, lnw = r[names.NONE], r[weakest]

        def delay(lg: float, lam: float) -> str:
            return "inf" if lam <= 0 else f"{lg / lam / rate:.2f}"

        print(f"| {t} | {ln0:.3g} | {weakest} | {lnw:.3g} | {delay(g50, ln0)} / {delay(g95, ln0)} "
              f"| {delay(g50, lnw)} / {delay(g95, lnw)} |", flush=True)


if __name__ == "__main__":
    main()
