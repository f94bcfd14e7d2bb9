"""Which pairs the models cannot separate: the model-based evidence rate of each dual that the
campaign rated Poor or ND (``design.distinguish`` states the computation).

For a pair ``a>b`` the dual ``h* = a+b`` must win against every other hypothesis of ``a``'s
level-1 bank (NONE, ``a`` alone, ``a`` + each other).  ``D`` is the expected evidence per
frame for ``h*`` against its weakest rival there, from the bank's own design (its linear
model, filters, ``Q_d`` and ``R``; complete failures; the dither; open loop).  ``D <= 0``: the
rival explains the data at least as well as the truth does, on average, whatever the floor,
threshold or dwell -- the pair is **physically indistinguishable** to this bank, and the
campaign rates it :data:`INDISTINGUISHABLE` instead of its measured Fair / Poor / ND (the
measured rating and its reason stay in the pair's summary; a pair rated Good keeps Good).

Only Poor and ND pairs are evaluated: a dual the models cannot separate is, on average, never
the likeliest hypothesis, so it is never declared and held (Good and Fair pairs were). Each
pair costs about a second and a half; its result is cached under the cache root
(``f16mmae.cache``, ``models/``) by the bank's content hash, the turbulence level and the pair.

The design is rebuilt from the bank's tuning at its design point and used only when its
filters are the bank's own (gains equal to 1e-9); otherwise, and for a failure mode other than
``complete`` or a turbulence level other than the design's (``light``) or ``none``, nothing is
evaluated and the summary says why.
"""
from __future__ import annotations

import json
import os
import tempfile

import numpy as np

from ... import names
from ...cache import cache_root
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
    """``{"rate_nats_per_frame": D, "against": the weakest rival, "indistinguishable": D <= 0}``
    of pair first>second."""
    rates = distinguish.evidence_rates(design, names.dual_name(first, second),
                                       distinguish.level1_competitors(first, second), calm=calm)
    weakest = min(rates, key=rates.get)
    d = float(rates[weakest])
    return {"rate_nats_per_frame": round(d, 6), "against": weakest,
            "indistinguishable": d <= 0.0}


#: The computation's revision, part of the cache's names: raise it when ``evidence`` changes.
REVISION = 1


def _cache_path(bank, turbulence: str):
    return cache_root() / "models" / f"dual_evidence_r{REVISION}_{bank.content_hash}_{turbulence}.json"


def _load_cached(path) -> dict:
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def _store_cached(path, entries: dict) -> None:
    """Write ``entries`` atomically; a cache that cannot be written is only slower."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
        with os.fdopen(fd, "w") as f:
            json.dump(entries, f, sort_keys=True)
        os.replace(tmp, path)
    except OSError:
        pass


def annotate(pairs: list[dict], bank, turbulence: str, mode: str) -> dict:
    """Evaluate every pair rated Poor or ND from the models, store it in the pair's ``models``
    field and re-rate the indistinguishable ones; returns the summary's ``models`` field (what
    was evaluated, or why nothing was)."""
    todo = [p for p in pairs if p["runs"] and p["rating"] in ("Poor", "ND")]
    if not todo:
        return {"evaluated": 0}
    if mode != "complete" or turbulence not in ("light", "none"):
        return {"evaluated": 0, "why_not": f"the models are evaluated for complete failures in light "
                                           f"turbulence or calm air, not {mode} in {turbulence}"}
    path = _cache_path(bank, turbulence)
    cached = _load_cached(path)
    missing = [p for p in todo if p["case"] not in cached]
    if missing:
        design, why = bank_design(bank)
        if design is None:
            return {"evaluated": 0, "why_not": why}
        for p in missing:
            cached[p["case"]] = evidence(design, p["first"], p["second"], calm=turbulence == "none")
        _store_cached(path, cached)
    for p in todo:
        p["models"] = dict(cached[p["case"]])
        if p["models"]["indistinguishable"]:
            note = (f"physically indistinguishable: D = {p['models']['rate_nats_per_frame']:.3g} nats/frame "
                    f"<= 0 against {p['models']['against']} (campaign.dual.models)")
            p["measured_rating"], p["rating"] = p["rating"], INDISTINGUISHABLE
            p["rating_reason"] = f"{note}; measured {p['measured_rating']}: {p['rating_reason']}"
            if p.get("absolute_rating") not in (None, "Good"):
                p["absolute_rating_reason"] = f"{note}; {p['absolute_rating_reason']}"
    return {"evaluated": len(todo),
            "indistinguishable": [p["case"] for p in todo if p["models"]["indistinguishable"]]}
