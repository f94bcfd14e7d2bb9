"""The dual-failure campaign (paper Sec. VI, Fig. 7): its config and run (``campaign``), the
scoring and rating of pairs (``scoring``), its figures (``figures``) and its report page
(``report``, registered on import)."""
from . import report  # noqa: F401 -- registers the page of kind "dual"
from .campaign import ALL_PAIRS, DualCampaign, pair_label, plan, run_campaign, run_seed, summarize

__all__ = ["ALL_PAIRS", "DualCampaign", "pair_label", "plan", "run_campaign", "run_seed", "summarize"]
