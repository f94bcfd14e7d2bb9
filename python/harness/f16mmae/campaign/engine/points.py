"""The flight points of a campaign (objects with ``label``, ``mach`` and ``alt_ft``: the envelope
campaign's selections, which ``campaign envelope``, ``maneuver`` and ``soak`` take): the one check
they all apply before planning."""
from __future__ import annotations

from ...truth.aircraft import check_flight_condition
from .config import CampaignError


def check_points(points) -> None:
    """CampaignError naming the problem: no point, a label used twice, one flight condition listed
    twice (its flights would be the same runs: the run key holds the condition, not the label),
    or a point outside the trimmable envelope."""
    if not points:
        raise CampaignError("no flight point selected")
    labels = [p.label for p in points]
    if len(set(labels)) != len(labels):
        raise CampaignError(f"point label(s) used twice in {', '.join(labels)}")
    seen: dict[tuple[float, float], str] = {}
    for p in points:
        key = (round(float(p.mach), 6), round(float(p.alt_ft), 3))
        if key in seen:
            raise CampaignError(f"points {seen[key]} and {p.label} are the same flight condition "
                                f"(Mach {p.mach}, {p.alt_ft:.0f} ft)")
        seen[key] = p.label
    for p in points:
        try:
            check_flight_condition(p.mach, p.alt_ft)
        except ValueError as exc:
            raise CampaignError(f"point {p.label}: {exc}") from None
