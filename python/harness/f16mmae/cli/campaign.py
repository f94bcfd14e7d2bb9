"""``f16mmae campaign KIND``: Monte Carlo campaigns, one module ``campaign_<kind>`` per kind of
``f16mmae.campaign.KINDS``, each with ``register(subparsers)``."""
from __future__ import annotations

import argparse
import importlib

from ..campaign import KINDS

DESCRIPTION = """\
Monte Carlo campaigns of closed-loop flights of the nonlinear JSBSim F-16 with the MMAE
estimator in the loop.

  single   every single failure (LS RS LF RF RUD VEL AOA PIT AZ ROL YAW AY) and the
           no-failure case NONE, N seeded runs each, the failure at 3.0 s of an 8-s
           flight, scored for isolation, missed/false alarms and detection latency
           (the paper's Figs. 3-6).
  dual     every ordered pair of failures (first at 3.0 s, second at 5.0 s), N runs
           each, rated Good / Fair / Poor / ND against the lone second failure
           (the paper's Fig. 7).
  envelope the nominal design flown at flight conditions around its design point: the
           single-failure campaign at each point (the paper's Fig. 9).
  soak     hours of failure-free flight at trim: false declarations per flight hour,
           how long each lasted and the hypotheses involved.
  detectability  detection probability against bias size and drift rate per sensor and
           against loss fraction per actuator, with 95 % intervals (how small a failure
           it sees).
  maneuver failures injected during climbs, descents, speed changes and 30-deg turns
           across the envelope: correct fraction, false declarations per maneuvering
           hour, latency.
  paper    the paper's whole campaign in one command: single, dual and envelope, each as
           its own command writes it, on one pool.
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "campaign",
        help=f"Monte Carlo campaigns ({', '.join(KINDS)})",
        description=DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    kinds = p.add_subparsers(dest="kind", metavar="KIND")
    for kind in KINDS:
        importlib.import_module(f"{__package__}.campaign_{kind}").register(kinds)
    importlib.import_module(f"{__package__}.campaign_paper").register(kinds)  # three kinds, one command
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])
