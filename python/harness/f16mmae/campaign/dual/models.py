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

**The window.** A separable pair (``D > 0``) may still be too slow for the flight: to be
declared the dual must raise its log-odds over the first failure alone (which holds the
probability after the switch) from the floor to ``ln(thr / (1 - thr))``.  From a floor ``P``
(every other hypothesis on it) that is ``ln(thr / (1 - thr)) - ln(P / (1 - (K - 1) P))``,
least at the largest floor that still lets a hypothesis pass the threshold,
``P* = (1 - thr) / (K - 1)``: ``L* = ln(thr^2 (K - 1) / (1 - thr)^2)`` (6.88 nats at thr 0.9,
K 13).  With ``D_1`` the evidence rate against the first failure alone, the drift gathers
``D_1 N`` nats in the ``N`` frames between the second failure and the flight's end less the
dwell; ``D_1 N < L*`` means that no admissible floor lets the drift declare the pair within
the flight (fluctuations still may: the floor reflects the log-odds, so this is a statement
about the mean, not a bound on every run).  Such a pair keeps its measured rating; the
``models`` field says so (``window``).

Only Poor and ND pairs are evaluated: a dual the models cannot separate is, on average, never
the likeliest hypothesis, so it is never declared and held (Good and Fair pairs were). Each
pair costs about a second and a half; its result is cached under the cache root
(``f16mmae.cache``, ``models/``) by the bank's content hash, the turbulence level and the pair.

The design is rebuilt from the bank's tuning at its design point and used only when its
filters are the bank's own (gains equal to 1e-9); otherwise, and for a failure mode other than
``complete``, a turbulence level other than the design's (``light``) or ``none``, or a dither
other than the default, nothing is evaluated and the summary says why.
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
from ...design.tuning import TuningError, load_tuning, tuning_from_dict
from .scoring import INDISTINGUISHABLE


def bank_design(bank):
    """(design, None) when the bank's tuning, redesigned at its point, gives its filters; else
    (None, why). The tuning is the one the bank's metadata records (a bank designed with a
    failure model or partial-loss hypotheses, e.g. ``tuned-cover``, whose name is no shipped
    tuning or names the shipped one it was derived from), else the shipped one it names; the
    partial-loss hypotheses are the metadata's ``partial_loss``."""
    meta = json.loads(bank.metadata) if isinstance(bank.metadata, str) else dict(bank.metadata or {})
    candidates, why = [], []
    if isinstance(meta.get("tuning"), dict):
        try:
            candidates.append(tuning_from_dict(meta["tuning"], source="the bank's metadata"))
        except (TuningError, ValueError) as exc:
            why.append(f"its metadata's tuning cannot be read ({exc})")
    try:
        candidates.append(load_tuning(bank.tuning))
    except (TuningError, FileNotFoundError, ValueError) as exc:
        why.append(f"the bank's tuning {bank.tuning!r} cannot be loaded ({exc})")
    for tuning in candidates:
        design = design_bank(bank.mach, bank.alt_ft, tuning=tuning, frame_rate_hz=bank.frame_rate_hz,
                             throttle_input=bank.nu > len(names.ACTUATORS),
                             partial_loss=tuple(meta.get("partial_loss", ())))
        wrong = _first_mismatch(bank, design)
        if wrong is None:
            return design, None
        why.append(f"the bank's filters are not its tuning's design (hypothesis {wrong})")
    return None, "; ".join(why) or "the bank records no tuning"


def _first_mismatch(bank, design) -> str | None:
    """The first hypothesis whose gains differ from the design's, None when all agree."""
    for h in bank.hypotheses:  # agreement to 1e-9 of each gain matrix's scale (a redesign's last bits follow the BLAS)
        k = np.asarray(h.k)
        if not np.allclose(design.filter(h.name).gains.k, k, rtol=0.0, atol=1e-9 * max(1.0, float(np.abs(k).max()))):
            return h.name
    return None


def evidence(design, first: str, second: str, calm: bool) -> dict:
    """``{"rate_nats_per_frame": D, "against": the weakest rival, "indistinguishable": D <= 0,
    "rate_vs_first": D_1}`` of pair first>second."""
    rates = distinguish.evidence_rates(design, names.dual_name(first, second),
                                       distinguish.level1_competitors(first, second), calm=calm)
    weakest = min(rates, key=rates.get)
    d = float(rates[weakest])
    return {"rate_nats_per_frame": round(d, 6), "against": weakest,
            "indistinguishable": d <= 0.0, "rate_vs_first": round(float(rates[first]), 6)}


def least_lift_nats(threshold: float, k: int = names.K_BANK) -> float:
    """``L*`` (module docstring): the least log-odds a dual must gain over the first failure
    alone to pass ``threshold``, from the largest floor at which any hypothesis can."""
    if not 0.5 < threshold < 1.0 or k < 2:
        raise ValueError(f"threshold must lie in (0.5, 1) and K >= 2, got {threshold!r}, {k!r}")
    return float(np.log(threshold ** 2 * (k - 1) / (1.0 - threshold) ** 2))


def window_check(rate_vs_first: float, frames: int, threshold: float) -> dict:
    """The drift over the window against ``L*``: ``{frames, nats, least_lift_nats,
    frames_to_least_lift, within}``."""
    lift = least_lift_nats(threshold)
    nats = rate_vs_first * frames
    return {"frames": int(frames), "nats": round(nats, 4), "least_lift_nats": round(lift, 4),
            "frames_to_least_lift": round(lift / rate_vs_first, 1) if rate_vs_first > 0 else None,
            "within": bool(nats >= lift)}


#: The computation's revision, part of the cache's names: raise it when ``evidence`` changes.
REVISION = 2


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


def annotate(pairs: list[dict], bank, turbulence: str, mode: str, window_frames: int | None = None,
             threshold: float = names.THRESHOLD_DEFAULT, dither_scale: float | None = 1.0) -> dict:
    """Evaluate every pair rated Poor or ND from the models, store it in the pair's ``models``
    field and re-rate the indistinguishable ones; with ``window_frames`` (the frames after the
    second failure less the dwell) the separable ones get the window's check (``window``, module
    docstring). ``dither_scale``: the campaign's dither (None: off); the models hold the default
    dither only. Returns the summary's ``models`` field (what was evaluated, or why nothing was)."""
    todo = [p for p in pairs if p["runs"] and p["rating"] in ("Poor", "ND")]
    if not todo:
        return {"evaluated": 0}
    if mode != "complete" or turbulence not in ("light", "none"):
        return {"evaluated": 0, "why_not": f"the models are evaluated for complete failures in light "
                                           f"turbulence or calm air, not {mode} in {turbulence}"}
    if dither_scale != 1.0:
        return {"evaluated": 0, "why_not": f"the models hold the default dither, not "
                                           f"{'none' if dither_scale is None else f'{dither_scale:g} times it'}"}
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
        elif window_frames is not None:
            w = p["models"]["window"] = window_check(p["models"]["rate_vs_first"], window_frames, threshold)
            if not w["within"]:
                p["rating_reason"] += (f"; separable (D = {p['models']['rate_nats_per_frame']:.3g} nats/frame) but "
                                       f"not within the flight: {w['nats']:.3g} nats in {w['frames']} frames against "
                                       f"first alone, < {w['least_lift_nats']:.3g} at any admissible floor "
                                       f"({w['frames_to_least_lift']:.0f} frames needed; campaign.dual.models)")
    return {"evaluated": len(todo),
            "indistinguishable": [p["case"] for p in todo if p["models"]["indistinguishable"]]}
