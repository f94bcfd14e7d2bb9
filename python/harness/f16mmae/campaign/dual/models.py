"""Which pairs the models cannot separate: the model-based evidence rate of each dual that the
campaign did not rate Good (issue 13 item 5; ``design.distinguish`` states the computation).

For a pair ``a>b`` the dual ``h* = a+b`` must win against every other hypothesis of ``a``'s
level-1 bank (NONE, ``a`` alone, ``a`` + each other).  ``D`` is the expected evidence per
frame for ``h*`` against its weakest rival there, from the bank's own design (its linear
model, filters, ``Q_d`` and ``R``; complete failures; the dither; open loop).  ``D <= 0``: the
rival explains the data at least as well as the truth does, on average, whatever the floor,
threshold or dwell -- the pair is **physically indistinguishable** to this bank, and the
campaign rates it :data:`INDISTINGUISHABLE` instead of its measured Fair / Poor / ND (the
measured rating and its reason stay in the pair's summary; a pair rated Good keeps Good).

The design is rebuilt from the bank's tuning at its design point and used only when its
filters are the bank's own (gains equal to 1e-9); otherwise, and for a failure mode other than
``complete`` or a turbulence level other than the design's (``light``) or ``none``, nothing is
evaluated and the summary says why.
"""
from __future__ import annotations

import numpy as np

from ... import names
from ...design import distinguish
from ...design.bank import design_bank
from ...design.tuning import TuningError, load_tuning
from .scoring import INDISTINGUISHABLE


def bank_design(bank):
    """(design, None) when the bank's tuning, redesigned at its point, gives its filters; else
    (None, why)."""
    try:
        tuning = load_tuning(bank.tuning)
    except (TuningError, FileNotFoundError, ValueError) as exc:
        return None, f"the bank's tuning {bank.tuning!r} cannot be loaded ({exc})"
    design = design_bank(bank.mach, bank.alt_ft, tuning=tuning, frame_rate_hz=bank.frame_rate_hz,
                         throttle_input=bank.nu > len(names.ACTUATORS))
    for h in bank.hypotheses:
        if not np.allclose(design.filter(h.name).gains.k, np.asarray(h.k), rtol=0.0, atol=1e-9):
            return None, f"the bank's filters are not its tuning's design (hypothesis {h.name})"
    return design, None


def evidence(design, first: str, second: str, calm: bool) -> dict:
    """``{"rate": D, "against": weakest rival, "seconds_to_lift_1e-9"}`` of pair first>second."""
    rates = distinguish.evidence_rates(design, names.dual_name(first, second),
                                       distinguish.level1_competitors(first, second), calm=calm)
    weakest = min(rates, key=rates.get)
    d = float(rates[weakest])
    return {"rate_nats_per_frame": round(d, 6), "against": weakest,
            "indistinguishable": d <= 0.0}


def annotate(pairs: list[dict], bank, turbulence: str, mode: str) -> dict:
    """Evaluate every pair not rated Good (relative or absolute) from the models, store it in
    the pair's ``models`` field and re-rate the indistinguishable ones; returns the summary's
    ``models`` field (what was evaluated, or why nothing was)."""
    todo = [p for p in pairs if p["runs"] and (p["rating"] != "Good" or p.get("absolute_rating") != "Good")]
    if not todo:
        return {"evaluated": 0}
    if mode != "complete" or turbulence not in ("light", "none"):
        return {"evaluated": 0, "why_not": f"the models are evaluated for complete failures in light "
                                           f"turbulence or calm air, not {mode} in {turbulence}"}
    design, why = bank_design(bank)
    if design is None:
        return {"evaluated": 0, "why_not": why}
    for p in todo:
        p["models"] = evidence(design, p["first"], p["second"], calm=turbulence == "none")
        if p["models"]["indistinguishable"]:
            note = (f"physically indistinguishable: D = {p['models']['rate_nats_per_frame']:.3g} nats/frame "
                    f"<= 0 against {p['models']['against']} (campaign.dual.models)")
            if p["rating"] != "Good":
                p["measured_rating"], p["rating"] = p["rating"], INDISTINGUISHABLE
                p["rating_reason"] = f"{note}; measured {p['measured_rating']}: {p['rating_reason']}"
            if p.get("absolute_rating") not in (None, "Good"):
                p["absolute_rating_reason"] = f"{note}; {p['absolute_rating_reason']}"
    return {"evaluated": len(todo),
            "indistinguishable": [p["case"] for p in todo if p["models"]["indistinguishable"]]}
