"""The cost of the estimator in the loop: one closed-loop flight against the truth model alone."""
from __future__ import annotations

import time

from ..truth import fly_raw
from .flight import fly


def measure_overhead(scenario, model_bank, repeats: int = 5, **estimator_options) -> dict:
    """Cost of one closed-loop flight against the truth model alone, in this process.

    ``truth_only_s``: the scenario flown on raw feedback with no estimator
    (``truth.fly_raw``); ``closed_loop_s``: the same scenario through :func:`fly` with the
    estimator in the loop and the probabilities recorded.  Each is timed by the CPU time of
    this thread (``time.thread_time``, which other load on the machine does not enter); the
    two alternate and the best of ``repeats`` of each is kept;
    ``ratio = closed_loop_s / truth_only_s`` (1.0 = the estimator and harness cost nothing)."""
    truth_only, closed = [], []
    fly(scenario, model_bank, estimator_options=estimator_options)  # warm: imports, estimator
    for _ in range(repeats):
        t0 = time.thread_time()
        fly_raw(scenario)
        t1 = time.thread_time()
        fly(scenario, model_bank, estimator_options=estimator_options)
        t2 = time.thread_time()
        truth_only.append(t1 - t0)
        closed.append(t2 - t1)
    a, b = min(truth_only), min(closed)
    return {"truth_only_s": round(a, 6), "closed_loop_s": round(b, 6),
            "ratio": round(b / a, 4), "duration_s": scenario.duration_s}
