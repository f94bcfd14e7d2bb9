"""The off-nominal campaign (paper Sec. VIII, Fig. 9): its points (``points``), its config,
run and per-point scoring (``campaign``), its figures (``figures``) and its report page
(``report``, registered on import)."""
from . import report  # noqa: F401 -- registers the page of kind "envelope"
from .campaign import EnvelopeCampaign, acceptable, plan, point_metrics, run_envelope, summarize, trim_offset
from .points import EnvelopeError, EnvelopePoint

__all__ = ["EnvelopeCampaign", "EnvelopeError", "EnvelopePoint", "acceptable", "plan", "point_metrics",
           "run_envelope", "summarize", "trim_offset"]
