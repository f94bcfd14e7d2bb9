"""The maneuver campaign (issue 12): failures injected during climbs, descents, speed changes
and turns across the envelope; its config, plan and scoring (``campaign``), figures
(``figures``) and report page (``report``, registered on import)."""
from . import report  # noqa: F401 -- registers the page of kind "maneuver"
from .campaign import MANEUVERS, ManeuverCampaign, group_metrics, maneuver_spec, plan, run_maneuver, summarize

__all__ = ["MANEUVERS", "ManeuverCampaign", "group_metrics", "maneuver_spec", "plan", "run_maneuver", "summarize"]
