"""HIL-style flights: the truth model here, the MMAE executive (``mmae-daemon``) over LCM.

The executive sits beside the flight control computer the way the design card draws it.
Per frame i (docs/INTERFACES.md), over LCM::

    harness                                         mmae-daemon
    z_i = truth.measure()
    publish F16_SENSORS {frame i, z_i}      ->      update(z_i): probabilities, z_hat_i
    wait MMAE_STATUS {frame i}              <-      publish status i
    u_i = fcs.command(z_hat_i | z_i, t_i)
    publish F16_COMMANDS {frame i, u_i}     ->      propagate(u_i)
    truth.advance(u_i)

The loop itself is :func:`f16mmae.loop.flight.fly`; the estimator it calls is
:class:`~f16mmae.lcm.remote.RemoteEstimator`, which speaks to the executive instead of holding a bank.
``lockstep`` waits for every status (as fast as possible: the same scenario and seed give
the in-process run's probabilities, to 1e-12); paced mode publishes frame i at wall time
t0 + i / rate and waits at most until the next frame is due: a status that misses that
deadline is counted and the FCS flies on the last z_hat it got.

Run markers (F16_RUN_MARKER: run_start with the scenario, failure at each injection time,
run_end) go into recorded logs for the record; the executive never subscribes to them.
Channel names are UPPER_SNAKE with an optional prefix (:func:`.channels.channels`).
"""
from __future__ import annotations

import json

from ..banks import bank_estimator_settings
from ..lcmt_run_marker import lcmt_run_marker
from ..loop.estimator import flown_bank_hash
from ..loop.estimator_options import with_closed_loop_defaults
from ..loop.flight import fly
from .channels import Channels, HilError
from .remote import RemoteEstimator, level0_hypotheses


# -- run markers ------------------------------------------------------------------------------------
def publish_marker(lc, chans: Channels, event: str, time_s: float, payload: dict) -> None:
    msg = lcmt_run_marker()
    msg.utime = int(round(time_s * 1e6))
    msg.event = event
    msg.payload_json = json.dumps(payload, sort_keys=True)
    lc.publish(chans.run_marker, msg.encode())


def fly_hil(scenario, model_bank, lc, chans: Channels, *, lockstep: bool = True,
            timeout_s: float = 5.0, feedback: str | None = None, on_frame=None,
            remote: RemoteEstimator | None = None, auth=None, estimator_options: dict | None = None):
    """Fly ``scenario`` against the executive reachable on ``lc``; returns the closed loop's
    FlightResult (timing gains ``link``: latency p50/p99/max, deadline misses, stale).
    ``on_frame(t, u, z, air_data)`` is called after each frame, as by loop.flight.fly; ``remote``: a
    RemoteEstimator of the caller's (then ``lockstep``/``timeout_s``/``auth`` are its own);
    ``auth``: a ``core.FrameAuth`` that signs what is sent and checks the statuses.
    With a bank that models the throttle, each command frame carries the frame's throttle
    command beside the surface commands (docs/INTERFACES.md), as the in-process loop hands it."""
    if remote is None:   # the status names the bank, or the turbulence bank set, the daemon runs
        remote = RemoteEstimator(lc, chans, lockstep=lockstep, timeout_s=timeout_s,
                                 expected_bank_hash=flown_bank_hash(model_bank, estimator_options or {}),
                                 initial_hypotheses=level0_hypotheses(model_bank), auth=auth)
    lockstep = remote.lockstep
    # what mmae-daemon applies: the bank's recommended settings (its typed fields), the
    # options it was started with (lcm.daemon.daemon_flags), and the closed loop's in force (the
    # adaptive dither with a turbulence bank set: the truth side reads the status's member and rho)
    remote.settings = with_closed_loop_defaults(bank_estimator_settings(model_bank, estimator_options))
    try:
        remote.reset(f"f16mmae hil: seed {scenario.seed}")
        publish_marker(lc, chans, "run_start", 0.0, {
            "scenario": scenario.to_dict(), "bank_hash": str(model_bank.content_hash),
            "lockstep": lockstep})
        pending = sorted((f.time_s, f.to_dict()) for f in scenario.failures)

        def frame_done(t, u, z, air_data):
            while pending and pending[0][0] <= t:
                publish_marker(lc, chans, "failure", t, pending.pop(0)[1])
            if on_frame is not None:
                on_frame(t, u, z, air_data)

        result = fly(scenario, model_bank, feedback=feedback, on_frame=frame_done, estimator=remote)
        link = remote.link.summary()
        publish_marker(lc, chans, "run_end", scenario.duration_s, {
            "frames": link["frames"], "declarations": result.declarations,
            "final_hypothesis": result.final_hypothesis})
        result.timing["link"] = link
        result.timing["mode"] = "lockstep" if lockstep else "paced"
        return result
    finally:
        remote.close()
