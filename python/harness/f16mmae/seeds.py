"""Seed namespaces: the flights that choose numbers never share a seed with the flights that judge them.

Every truth-model flight is seeded by one integer ``s >= 1`` (JSBSim turbulence and the sensor
noise generator; JSBSim maps 0 to 1).  Seeds are drawn from two disjoint namespaces:

* **Tuning** -- the draws of everything that chooses a number: ``design.calibrate`` and
  ``design.convergence`` fly :data:`TUNING_FLIGHT_SEEDS` (1-8), and the shipped tuned bank's
  dither and estimator settings were chosen on the single campaign at campaign seed 1, runs
  0-19, i.e. the seeds ``derived_seed("single", 1, c, n)`` for every single case ``c`` and
  ``n < 20`` (:data:`TUNING_CAMPAIGN`).  :func:`tuning_seeds` is that finite set.
* **Evaluation** -- the draws of every campaign: run ``place`` (e.g. case and run index) of a
  campaign of kind ``k`` at campaign seed ``S`` flies
  ``evaluation_seed(k, S, *place) = derived_seed("evaluation", k, S, *place)``, re-drawn as
  ``derived_seed("evaluation", k, S, *place, "redraw", i)`` for ``i = 1, 2, ...`` while the
  value lies in the tuning set.  The namespaces are therefore disjoint by construction;
  ``--seed`` chooses ``S`` within evaluation.

``derived_seed(*parts) = 1 + (SHA-256("p1:p2:...") mod (2^31 - 2))``: deterministic, >= 1,
independent of the executor and of the order runs finish.
"""
from __future__ import annotations

import functools
import hashlib

from .names import SINGLE_HYPOTHESES

#: Seeds of the no-failure and failure flights that calibration and convergence fly.
TUNING_FLIGHT_SEEDS: tuple[int, ...] = tuple(range(1, 9))
#: The campaign runs the shipped tuned bank's settings were chosen on: (kind, seed, runs).
TUNING_CAMPAIGN = ("single", 1, 20)
EVALUATION = "evaluation"


def derived_seed(*parts) -> int:
    """``1 + (SHA-256("p1:p2:...") mod (2^31 - 2))`` (see the module docstring)."""
    digest = hashlib.sha256(":".join(map(str, parts)).encode()).digest()
    return 1 + int.from_bytes(digest[:8], "big") % (2**31 - 2)


@functools.lru_cache(maxsize=1)
def tuning_seeds() -> frozenset[int]:
    """Every seed of the tuning namespace."""
    kind, campaign_seed, runs = TUNING_CAMPAIGN
    drawn = {derived_seed(kind, campaign_seed, c, n) for c in SINGLE_HYPOTHESES for n in range(runs)}
    return frozenset(TUNING_FLIGHT_SEEDS) | drawn


def evaluation_seed(kind: str, campaign_seed: int, *place, tuning: frozenset[int] | None = None) -> int:
    """The seed of one campaign run, never a tuning seed (see the module docstring).
    ``tuning`` replaces :func:`tuning_seeds` (for tests of the re-draw)."""
    excluded = tuning_seeds() if tuning is None else tuning
    seed = derived_seed(EVALUATION, kind, campaign_seed, *place)
    i = 0
    while seed in excluded:
        i += 1
        seed = derived_seed(EVALUATION, kind, campaign_seed, *place, "redraw", i)
    return seed
