"""Test support shared by the tests of the scheduled estimator: a one-node schedule, and a flight
that records the probability floor in force after every update."""
from __future__ import annotations

import numpy as np

from f16mmae import core, names
from f16mmae.design.bank import design_bank, to_model_bank
from f16mmae.design.tuning import load_tuning, tuning_from_dict


def one_node_schedule(directory):
    """A one-node schedule (written into ``directory``) of the constant=VEL+ROL design at Mach
    0.4, 20,000 ft: a scheduled bank, so the scheduled estimator's defaults apply to it."""
    base = load_tuning("tuned").to_dict()
    base["estimator"].pop("dwell_nats_per_hypothesis", None)   # a scheduled node's: the frame dwell alone
    tun = tuning_from_dict({**base, "failure_model": {"default": "complete", "constant": ["VEL", "ROL"]}},
                           default_name="vel-rol")
    mb = to_model_bank(design_bank(0.4, 20_000.0, tun))
    path = directory / "one.f16sched"
    core.save_schedule([0.4], [20000.0], [(0, 0, mb, np.zeros(names.NX))], primary=0, path=str(path))
    return core.load_bank(str(path))


def floors_in_force(scenario, model_bank, est):
    """(FlightResult, the level-0 floor in force after each update) of ``scenario`` flown with
    ``model_bank`` and the in-process estimator ``est`` (loop.estimator.Estimator)."""
    from f16mmae.loop.flight import fly
    floors = []   # after each frame's update (propagate leaves the floor alone)
    result = fly(scenario, model_bank, estimator=est,
                 on_frame=lambda *frame: floors.append(est._bank.p_min_in_force))
    return result, np.asarray(floors)
