"""Detectability curves (issue 13 item 3): detection probability against bias size and drift
rate per sensor and against loss fraction per actuator; its config, plan and run
(``campaign``), its figures (``figures``) and its table and pages (``report``, registered on
import)."""
from . import report  # noqa: F401 -- registers the page of kind "detectability"
from .campaign import (DetectabilityCampaign, plan, run_campaign, score_detection, sigma_of, summarize,
                       summarize_point, truth_value)

__all__ = ["DetectabilityCampaign", "plan", "run_campaign", "score_detection", "sigma_of", "summarize",
           "summarize_point", "truth_value"]
