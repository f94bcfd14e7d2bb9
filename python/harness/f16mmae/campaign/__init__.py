"""Monte Carlo campaigns of closed-loop runs: an engine plus one folder per kind.

* ``engine``   -- what every kind shares: config, seeds, runner, executor, store, scoring;
* ``single``   -- the single-failure campaign (paper Sec. V, Figs. 3-6);
* ``dual``     -- every ordered pair of failures, rated against the lone second failure
  (paper Sec. VI, Fig. 7);
* ``envelope`` -- the design flown at the paper's off-nominal points (Sec. VIII, Fig. 9) or at
  random points over the envelope;
* ``soak``     -- hours of failure-free flight: false declarations per flight hour;
* ``detectability`` -- detection probability against bias, drift and loss size;
* ``maneuver`` -- failures injected during climbs, descents, speed changes and turns.

:data:`KINDS` is the one list of kinds.  A kind is a folder here of that name, whose import
registers its HTML and Markdown pages with ``f16mmae.report``, plus the command-line module
``f16mmae.cli.campaign_<kind>``; the import-linter contracts in pyproject.toml name the same
folders (a test checks they agree).  Kinds never import each other, and the engine imports
none of them.
"""
from __future__ import annotations

import importlib
from types import ModuleType

#: Every campaign kind, in the order ``f16mmae campaign --help`` lists them.
KINDS = ("single", "dual", "envelope", "soak", "detectability", "maneuver")


def import_kinds() -> list[ModuleType]:
    """Import every kind's package (which registers its report pages), in :data:`KINDS` order."""
    return [importlib.import_module(f"{__name__}.{kind}") for kind in KINDS]
