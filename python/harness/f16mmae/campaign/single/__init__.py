"""The single-failure campaign (paper Sec. V, Figs. 3-6): its config and run (``campaign``),
its figures (``figures``) and its report page (``report``, registered on import)."""
from . import report  # noqa: F401 -- registers the page of kind "single"
from .campaign import SingleCampaign, make_figures, run_campaign, summarize

__all__ = ["SingleCampaign", "make_figures", "run_campaign", "summarize"]
