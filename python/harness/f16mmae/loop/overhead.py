"""The cost of the estimator in the loop: one closed-loop flight against the truth model alone."""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..names import FRAME_RATE_HZ
from ..truth import FlightControlSystem, TruthModel, fly_raw
from .estimator import Estimator
from .flight import fly, models_throttle


def _frames_alone(scenario, model_bank, estimator_options: dict, closed: bool) -> float:
    """CPU time of the one C++ call of a flight (set-up and Python around it untimed): the
    truth's frames on raw feedback (``TruthModel.fly_frames``, as ``fly_raw`` flies them) or,
    ``closed``, the closed loop's frames with a fresh estimator (``TruthModel.fly_closed_loop``,
    as ``fly`` flies them: no truth log, probabilities recorded)."""
    truth = TruthModel(scenario, record_log=not closed)
    fcs = FlightControlSystem(truth.trim, dither=scenario.dither, ari=scenario.ari, pilot=truth.pilot())
    truth.attach(fcs)
    n = int(round(scenario.duration_s * FRAME_RATE_HZ))
    est = Estimator.fresh(model_bank, **estimator_options) if closed else None
    t0 = time.thread_time()
    if closed:
        truth.fly_closed_loop(est.core_bank, n, scenario.feedback == "mmae", True)
    else:
        truth.fly_frames(n)
    t = time.thread_time() - t0
    truth.close()
    return t


def measure_overhead(scenario, model_bank, repeats: int = 5, pieces: bool = False, **estimator_options) -> dict:
    """Cost of one closed-loop flight against the truth model alone, in this process.

    ``truth_only_s``: the scenario flown on raw feedback with no estimator
    (``truth.fly_raw``); ``closed_loop_s``: the same scenario through :func:`fly` with the
    estimator in the loop and the probabilities recorded.  Each is timed by the CPU time of
    this thread (``time.thread_time``, which other load on the machine does not enter); the
    two alternate and the best of ``repeats`` of each is kept;
    ``ratio = closed_loop_s / truth_only_s`` (1.0 = the estimator and harness cost nothing).

    ``pieces`` (the cpp engine; a fixed-size bank and no gust burst, else ignored): also, interleaved with those,
    the one C++ call of each flight alone (:func:`_frames_alone`; best of ``repeats``:
    ``truth_frames_s``, ``closed_loop_frames_s``), ``median_ratio`` (of the medians), and
    ``pieces`` = where the closed loop's extra goes, from the best timings (s): ``extra`` =
    closed loop - truth alone; ``estimator`` its frames' estimator part, counted inside the C++
    loop (``timing.estimator_s``, wall time: its best);
    ``truth_beside`` = closed-loop frames - truth frames - estimator (the truth's own steps run
    slower beside the estimator, each evicting the other's cache lines); ``python`` = extra -
    (closed-loop frames - truth frames) (the Python around the call: estimator reset, the
    result).  A bank that models the throttle: both sides fly the scheduled throttle dither
    (``fly`` adds it for such a bank)."""
    if models_throttle(model_bank):   # as fly flies such a bank: both sides fly the throttle dither
        scenario = dataclasses.replace(scenario, dither=scenario.dither.with_scheduled_throttle())
    truth_only, closed, est_s, raw_frames, cl_frames = [], [], [], [], []
    fly(scenario, model_bank, estimator_options=estimator_options)  # warm: imports, estimator
    # the pieces need the flights fly flies in one C++ call (a fixed-size bank, no gust burst)
    pieces = pieces and Estimator.fresh(model_bank, **estimator_options).fixed_size and scenario.gust_burst is None
    for _ in range(repeats):
        t0 = time.thread_time()
        fly_raw(scenario)
        t1 = time.thread_time()
        result = fly(scenario, model_bank, estimator_options=estimator_options)
        t2 = time.thread_time()
        truth_only.append(t1 - t0)
        closed.append(t2 - t1)
        est_s.append(result.timing["estimator_s"])
        if pieces:
            raw_frames.append(_frames_alone(scenario, model_bank, estimator_options, closed=False))
            cl_frames.append(_frames_alone(scenario, model_bank, estimator_options, closed=True))
    a, b = min(truth_only), min(closed)
    out = {"truth_only_s": round(a, 6), "closed_loop_s": round(b, 6),
           "ratio": round(b / a, 4), "duration_s": scenario.duration_s}
    if pieces:
        best = {"est": min(est_s), "raw_frames": min(raw_frames), "cl_frames": min(cl_frames)}
        extra, frames_extra = b - a, best["cl_frames"] - best["raw_frames"]
        out["truth_frames_s"] = round(best["raw_frames"], 6)
        out["closed_loop_frames_s"] = round(best["cl_frames"], 6)
        out["median_ratio"] = round(float(np.median(closed) / np.median(truth_only)), 4)
        out["pieces"] = {"extra_s": round(extra, 6), "estimator_s": round(best["est"], 6),
                         "truth_beside_s": round(frames_extra - best["est"], 6),
                         "python_s": round(extra - frames_extra, 6)}
    return out
