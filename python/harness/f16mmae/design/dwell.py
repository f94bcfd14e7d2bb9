"""The declaration dwell a bank recommends, from its no-failure calibration flights.

A failure is declared when one hypothesis holds ``p_k > threshold`` on ``dwell_frames``
consecutive frames, ``dwell_frames = max(1, round(dwell_s * frame_rate_hz))``
(``cpp/f16mmae/declarer.h``).  ``longest_excursion`` runs the estimator the bank makes
(``core.HierarchicalBank`` with the bank's recommended settings) over no-failure flights
with the dwell set beyond the flights' length, so that nothing is declared and the bank stays
at level 0 with NONE presumed, and measures L, the longest stretch of consecutive frames in
which one failure hypothesis (k != NONE) is above the threshold.  Up to its first declaration
a run with any dwell d is that same run (the dwell acts only through the declaration), so

    dwell d declares a failure in these flights  <=>  dwell_frames(d) <= L.

``calibrated_dwell`` recommends the smallest candidate (``DWELL_CANDIDATES_S``) with
``dwell_frames(d) > L``: the shortest wait that the calibration flights' noise does not fill.
The flights are the no-failure tuning flights of ``calibrate.py`` (``calibrate.node_flights``:
full truth, light turbulence, the FCS on raw feedback, seeds 1-8), the same ones stage 1
calibrates the pseudonoise on.  For the ``cover`` failure models the stretch is what sets the
dwell: a failed surface whose position is free explains a gust for a fraction of a second
(docs/results/failure_models.md).

Run: ``python -m f16mmae.design.dwell BANK`` prints L per flight and the recommendation.
"""
from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from .. import names

#: The dwells (s) a calibration chooses from, shortest first: the core's default (the
#: paper-model banks' 0.25 s) and quarter-second steps up to a second.
DWELL_CANDIDATES_S: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0)
#: The dwell the excursions are measured with: longer than any calibration flight (8 s).
MEASURE_DWELL_S = 30.0


def dwell_frames(dwell_s: float, frame_rate_hz: float) -> int:
    """Consecutive frames a declaration needs (``cpp/f16mmae/declarer.h``)."""
    return max(1, int(round(dwell_s * frame_rate_hz)))


def excursions(model_bank, flights) -> list[dict[str, int]]:
    """Per flight, ``{hypothesis: L_k}``: for each failure hypothesis k that rises above the
    bank's threshold, the longest stretch of consecutive frames in which it holds ``p_k >``
    threshold, with the bank's settings and the dwell MEASURE_DWELL_S (module docstring).
    ``flights``: no-failure records (``u``, ``z``: perturbations from the bank's trim).  Raises
    ValueError if a failure is declared all the same (a flight longer than MEASURE_DWELL_S)."""
    from .. import core
    from .calibrate import absolute_frames

    settings = {**model_bank.estimator_settings, "dwell_s": MEASURE_DWELL_S}
    threshold = float(settings["threshold"])
    bank = core.HierarchicalBank(model_bank, **settings)
    hyps = list(bank.hypotheses)   # the level-0 bank (its partial hypotheses too, if it has any)
    out = []
    for fl in flights:
        bank.reset()
        u, z = absolute_frames(model_bank, fl)
        longest: dict[str, int] = {}
        run, cand = 0, -1
        for i in range(len(z)):
            if bank.step(z[i], u[i]) is not None:
                raise ValueError(f"a failure was declared at frame {i} with a dwell of {MEASURE_DWELL_S} s: "
                                 "the flights must be shorter than that")
            p = np.asarray(bank.probabilities)
            k = int(np.argmax(p))
            if k != 0 and p[k] > threshold:
                run = run + 1 if k == cand else 1
                cand = k
                longest[hyps[k]] = max(longest.get(hyps[k], 0), run)
            else:
                run, cand = 0, -1
        out.append(longest)
    return out


def longest_excursion(model_bank, flights) -> list[tuple[int, str]]:
    """Per flight, ``(L, hypothesis)``: the longest of the flight's ``excursions`` and which
    hypothesis held it (``"NONE"``, 0 when none rises above the threshold; the first in bank
    order on a tie)."""
    from .. import core

    hyps = list(core.HierarchicalBank(model_bank).hypotheses)
    out = []
    for longest in excursions(model_bank, flights):
        best, who = 0, names.NONE
        for h in hyps:
            if longest.get(h, 0) > best:
                best, who = longest[h], h
        out.append((best, who))
    return out


def calibrated_dwell(model_bank, flights, candidates: tuple[float, ...] = DWELL_CANDIDATES_S) -> dict:
    """The recommended dwell (module docstring): the smallest candidate whose
    ``dwell_frames`` exceeds the flights' longest excursion L; the largest candidate if none
    does (``bound_met`` False).  Returns ``{dwell_s, longest_frames, longest_s, hypothesis,
    bound_met, per_flight: [[L, hypothesis], ...]}``.  Deterministic for given flights."""
    rate = float(model_bank.frame_rate_hz)
    per = longest_excursion(model_bank, flights)
    longest, who = max(per, key=lambda r: r[0])
    ok = [d for d in sorted(candidates) if dwell_frames(d, rate) > longest]
    return {"dwell_s": float(ok[0] if ok else max(candidates)), "longest_frames": int(longest),
            "longest_s": round(longest / rate, 4), "hypothesis": who, "bound_met": bool(ok),
            "per_flight": [[int(n), h] for n, h in per]}


def with_calibrated_dwell(design, flights=None):
    """``(design, result)``: the unscheduled ``design`` (``bank.BankDesign``) with its tuning's
    recommended ``dwell_s`` replaced by ``calibrated_dwell`` on ``flights`` (default: the
    no-failure tuning flights at the design point in the tuning's turbulence,
    ``calibrate.node_flights``), and the calibration's result."""
    from .bank import to_model_bank
    from .calibrate import node_flights

    if flights is None:
        flights = node_flights(design.mach, design.alt_ft, design.tuning.turbulence)
    res = calibrated_dwell(to_model_bank(design), flights)
    tun = dataclasses.replace(design.tuning, estimator={**design.tuning.estimator, "dwell_s": res["dwell_s"]})
    return dataclasses.replace(design, tuning=tun), res


def main(argv=None) -> dict:
    from .. import core
    from .calibrate import node_flights

    ap = argparse.ArgumentParser(prog="python -m f16mmae.design.dwell", description=__doc__.split("\n\n")[0])
    ap.add_argument("bank", help="an unscheduled bank file (its trim point and settings are used)")
    ap.add_argument("--per-hypothesis", action="store_true",
                    help="also print each failure hypothesis' longest excursion over the flights")
    args = ap.parse_args(argv)
    mb = core.load_bank(args.bank)
    flights = node_flights(float(mb.mach), float(mb.alt_ft), "light")
    res = calibrated_dwell(mb, flights)
    for s, (n, h) in enumerate(res["per_flight"], start=1):
        print(f"flight {s}: longest excursion {n} frames ({n / float(mb.frame_rate_hz):.3f} s) {h}")
    print(f"recommended dwell {res['dwell_s']:g} s (longest {res['longest_frames']} frames, "
          f"{res['hypothesis']}; bound met: {res['bound_met']})")
    if args.per_hypothesis:
        rate = float(mb.frame_rate_hz)
        per = excursions(mb, flights)
        for h in mb.hypothesis_names[1:names.K_BANK]:
            n = max(fl.get(h, 0) for fl in per)
            print(f"{h:4s} longest excursion {n:3d} frames ({n / rate:.3f} s): a dwell of "
                  f"{n + 1} frames ({(n + 1) / rate:.3f} s) or more declares it in none of these flights")
    return res


if __name__ == "__main__":
    main()
