"""Seeds of campaign runs: each a pure function of the campaign's kind, its seed and the run's
place in the plan, drawn from the evaluation namespace, which tuning never touches
(:mod:`f16mmae.seeds` defines both namespaces and proves them disjoint)."""
from __future__ import annotations

from ...seeds import derived_seed, evaluation_seed

__all__ = ["derived_seed", "evaluation_seed"]
