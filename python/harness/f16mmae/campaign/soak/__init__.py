"""The soak campaign: long failure-free flights, false declarations per flight hour
(issue 14): its config and run (``campaign``), the false-declaration arithmetic
(``episodes``), its figures (``figures``) and its report page (``report``, registered on import)."""
from . import report  # noqa: F401 -- registers the page of kind "soak"
from .campaign import GOALS_PER_H, SoakCampaign, run_soak, summarize

__all__ = ["GOALS_PER_H", "SoakCampaign", "run_soak", "summarize"]
