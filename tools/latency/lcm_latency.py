"""Latency of the MMAE executive over LCM beside a bare C++ echo, from one run.

``f16mmae bench lcm [--duration 60] [--lcm-url URL] [--json FILE]`` (from a source checkout;
or ``python tools/latency/lcm_latency.py ...``). Not installed with the package: it needs the
latency tools of this folder, which are built with the project and never installed.

Runs itself inside a private network namespace (``f16mmae.lcm.netns``: loopback only, with
multicast), so no packet reaches a real interface; ``--realtime`` then needs a host that grants
SCHED_FIFO inside an unprivileged user namespace.

Starts ``mmae-daemon`` (the shipped tuned bank) and ``lcm-echo-f16`` (republishes each
message byte for byte: the transport's own round trip) on one LCM URL, then flies the truth
model in real time at 64 Hz against the daemon (``f16mmae hil`` paced mode, no failure,
light turbulence). Each frame i:

    t_i            publish F16_SENSORS i, wait for MMAE_STATUS i       -> executive latency
                   FCS, publish F16_COMMANDS i, truth advance
    t_i + T/2      publish the same sensor frame on ECHO_PING, wait ECHO_PONG -> echo latency

so both round trips go through the same Python process, the same LCM library and the same
loopback, interleaved in the same run (never overlapping), each after the processes have
idled for several milliseconds, as a sensor frame finds them. (Measured here: a round trip
after 14 ms of idling costs ~150 us on this kind of virtual machine, after 0.5 ms ~45 us,
for the echo and the executive alike: the wake-up of idle vCPUs, not LCM, dominates. So the
echo must not be pinged right after the busy part of the frame.) The echo uses the next UDP port
of the same multicast group: with udpm every LCM instance on a port receives (and discards)
every message on it, so sharing one port would wake the daemon for the echo's traffic and
the echo for the executive's. Latency is
publish -> receive in this process (time.perf_counter_ns). A deadline miss is a status not
received before frame i+1 is due (15.625 ms). Reported: p50, p99, max of both, the
executive's excess over the echo at p50 and p99 (target: <= 20 us at p99), misses (target:
zero), and the daemon's own step-time summary line.

Placement (``--placement``): by default nothing is pinned (``free``), as the daemon would
run. ``split`` puts the harness on the first CPU and the daemon and the echo on the last (the
executive on a core of its own); ``shared`` puts all three on the last CPU. Measured on a
2-vCPU VM (60-s runs): ``shared`` gave the tightest tails (p99 ~250 us against ~500 us
unpinned) but the harness's Python then evicts the daemon's caches just before each frame;
none of the three made the p99 difference between the round trips reproducible to 20 us --
the host's scheduling sets both tails.

Then, with the same two processes, a controlled pairing (``--pairs N``, default 1000): N
pairs of round trips with no truth model in between, each preceded by the same idle time
(``--idle-ms``, default 14, what a 64-Hz frame leaves), the order alternating within the
pairs -- the executive's excess over the echo under identical conditions.

Two readings that the round trips' host noise does not blur:
- inside each process, from the message's callback to the reply published (lcm_publish
  returned): the daemon's sensor-to-publish (decode, step, encode, publish) beside the echo's
  message-to-publish (publish alone) -- what the executive adds, without the wake-up chain
  before the callback (UDP receive thread, notify pipe, main thread) that both share.
  ``--echo-work-us 5`` makes the echo spend 5 us of register-only work first, as the
  executive spends its step: measured, the two then cost the same (+1.0 us at p50): a publish
  made a few us after the message came wakes a receiver that has gone idle meanwhile;
- the host floor, before anything else starts: f16mmae-idle-jitter times 5 us of
  register-only work back to back and after a 64-Hz frame's idle, on the daemon's CPUs. Its
  p99 after the idle is the least tail any step of that length can have on this host.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import lcm
import numpy as np

from f16mmae.banks import load_bank
from f16mmae.lcm.channels import HilError, channels
from f16mmae.lcm.daemon import DaemonProcess, pin_to, statistics_line
from f16mmae.lcm.hil import fly_hil
from f16mmae.lcm.netns import NetnsError, reexec_in_private_netns
from f16mmae.lcm.remote import RemoteEstimator, level0_hypotheses
from f16mmae.lcmt_command_frame import lcmt_command_frame
from f16mmae.lcmt_mmae_reset import lcmt_mmae_reset
from f16mmae.lcmt_sensor_frame import lcmt_sensor_frame
from f16mmae.names import FRAME_RATE_HZ, NZ
from f16mmae.truth import Scenario

#: A private port and channel prefix, so the benchmark neither hears nor disturbs other traffic.
DEFAULT_URL = "udpm://239.255.76.67:7671?ttl=0"
PREFIX = "BENCH_"


def _quantiles_us(ns: list[int]) -> dict:
    a = np.array(ns, dtype=float) / 1e3
    if a.size == 0:
        return {"n": 0, "p50": None, "p99": None, "max": None}
    return {"n": int(a.size), "p50": round(float(np.percentile(a, 50)), 1),
            "p99": round(float(np.percentile(a, 99)), 1), "max": round(float(a.max()), 1)}


def find_tool(name: str) -> Path:
    """A latency tool (``lcm-echo-f16``, ``f16mmae-idle-jitter``): built with the project but
    not installed, so looked for in $F16MMAE_TOOLS_DIR, then the build trees of this source
    checkout (``build/py`` of ``make build``, ``build/cpp`` of ``make ctest``). Raises HilError
    naming the places looked at."""
    root = Path(__file__).resolve().parents[2]  # tools/latency -> the checkout
    places = [Path(d) for d in filter(None, [os.environ.get("F16MMAE_TOOLS_DIR")])] + \
        [root / "build" / tree / "tools" / "latency" for tree in ("py", "cpp")]
    for d in places:
        if (d / name).is_file() and os.access(d / name, os.X_OK):
            return d / name
    raise HilError(f"cannot find {name}: looked in {', '.join(map(str, places))}; the latency tools are "
                   f"built from a source checkout ('make build'), never installed (or set F16MMAE_TOOLS_DIR)")


def host_floor(server_cpus: set[int] | None, samples: int = 300) -> dict:
    """f16mmae-idle-jitter on the daemon's CPUs: a fixed 5-us register-only computation timed
    back to back and after a 64-Hz frame's idle -- the tail this host adds to any step of that
    length. ``{idle_us: {count, p50, p99, max}}``, from its statistics line."""
    frame_us = 1e6 / FRAME_RATE_HZ
    out = subprocess.run([str(find_tool("f16mmae-idle-jitter")), "--work-us", "5", "--samples", str(samples),
                          "--idle-us", f"0,{frame_us:g}"], capture_output=True, text=True, check=True,
                         timeout=60, preexec_fn=pin_to(server_cpus)).stdout
    return {float(k): v for k, v in statistics_line(out, "f16mmae-idle-jitter")["idle_us"].items()}


def echo_name(wake_lead_us: float, work_us: float) -> str:
    """The echo's row label: a bare echo, or the control it was made into."""
    parts = ([f"wakes {wake_lead_us:g} us early"] if wake_lead_us else []) + \
        ([f"+{work_us:g} us work"] if work_us else [])
    return "C++ echo, " + ", ".join(parts) if parts else "bare C++ echo"


def next_port_url(url: str) -> str:
    """The same udpm URL on the next port (``udpm://G:P?o`` -> ``udpm://G:P+1?o``)."""
    if not url.startswith("udpm://"):
        return url
    head, sep, opts = url.partition("?")
    group, _, port = head[len("udpm://"):].rpartition(":")
    return f"udpm://{group}:{int(port) + 1}{sep}{opts}"


def paired_round_trips(lc, lc_echo, chans, ping: str, pong: str, model_bank, pairs: int,
                       idle_s: float) -> tuple[list[int], list[int]]:
    """Executive and echo round trips in alternating order, each after ``idle_s`` of idling
    (a fresh flight on the executive: MMAE_RESET, then frames 0..pairs-1 near trim)."""
    got = {"t": 0, "ns": None}

    def on_reply(channel, data):
        if got["ns"] is None:
            got["ns"] = time.perf_counter_ns() - got["t"]

    subs = [(lc, lc.subscribe(chans.status, on_reply)), (lc_echo, lc_echo.subscribe(pong, on_reply))]
    reset = lcmt_mmae_reset()
    reset.reason = "lcm_latency: paired round trips"
    lc.publish(chans.reset, reset.encode())
    rng = np.random.default_rng(1)
    z_trim, u_trim = np.array(model_bank.z_trim), [float(v) for v in model_bank.u_trim]
    out = {"ex": [], "echo": []}

    def round_trip(which, inst, channel, data):
        time.sleep(idle_s)
        got["ns"] = None
        got["t"] = time.perf_counter_ns()
        inst.publish(channel, data)
        end = time.perf_counter() + 0.1
        while got["ns"] is None and (left := end - time.perf_counter()) > 0:
            inst.handle_timeout(max(1, int(left * 1000)))
        if got["ns"] is not None:
            out[which].append(got["ns"])

    try:
        for i in range(pairs):
            f = lcmt_sensor_frame()
            f.utime, f.frame, f.valid = i * 15625, i, [True] * len(z_trim)
            f.z = [float(v) for v in z_trim + 1e-4 * rng.standard_normal(len(z_trim))]
            data = f.encode()
            legs = [("ex", lc, chans.sensors, data), ("echo", lc_echo, ping, data)]
            for leg in (legs if i % 2 == 0 else legs[::-1]):
                round_trip(*leg)
            c = lcmt_command_frame()
            c.utime, c.frame, c.u_rad = f.utime, i, u_trim
            lc.publish(chans.commands, c.encode())
    finally:
        for inst, sub in subs:
            inst.unsubscribe(sub)
    return out["ex"], out["echo"]


def run(duration_s: float = 60.0, lcm_url: str = DEFAULT_URL, bank: str = "tuned",
        realtime: int = 0, pairs: int = 1000, idle_ms: float = 14.0, warm_lead_us: float | None = None,
        echo_wake_lead_us: float = 0.0, placement: str = "free", rewarm_us: float | None = None,
        echo_rewake_us: float = 0.0, echo_work_us: float = 0.0) -> dict:
    label, path, model_bank = load_bank(bank)
    scenario = Scenario.from_dict({"mach": float(model_bank.mach), "alt_ft": float(model_bank.alt_ft),
                                   "turbulence": "light", "duration_s": duration_s, "seed": 1,
                                   "feedback": "mmae", "failure": []})
    chans = channels(PREFIX)
    ping, pong = PREFIX + "ECHO_PING", PREFIX + "ECHO_PONG"
    harness_cpus, server_cpus = place(placement)
    floor = host_floor(server_cpus)  # before any other process of the benchmark runs
    if harness_cpus is not None:  # before LCM's threads exist: they inherit it
        os.sched_setaffinity(0, harness_cpus)
    if realtime:  # this process (the receiver of both round trips) too, before LCM's threads
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(realtime))
        except PermissionError:
            print(f"warning: SCHED_FIFO {realtime} refused for the benchmark process", file=sys.stderr)
    lc = lcm.LCM(lcm_url)
    echo_url = next_port_url(lcm_url)
    lc_echo = lcm.LCM(echo_url)
    rt = ("--realtime", str(realtime)) if realtime else ()
    wake = ("--wake-lead-us", f"{echo_wake_lead_us:g}", "--rewake-us", f"{echo_rewake_us:g}",
            "--rate-hz", f"{FRAME_RATE_HZ:g}", "--work-us", f"{echo_work_us:g}")
    echo = subprocess.Popen([str(find_tool("lcm-echo-f16")), "--lcm-url", echo_url, "--in", ping,
                             "--out", pong, *rt, *wake], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=pin_to(server_cpus))
    if "ready" not in echo.stdout.readline():
        echo.kill()
        raise HilError(f"lcm-echo-f16 did not start: {echo.communicate()[1].strip()}")
    echo_ns: list[int] = []
    echo_lost = 0
    state = {"t_pub": 0, "got": False}

    def on_pong(channel, data):
        echo_ns.append(time.perf_counter_ns() - state["t_pub"])
        state["got"] = True

    sub = lc_echo.subscribe(pong, on_pong)
    frame = lcmt_sensor_frame()
    frame.z, frame.valid = [0.0] * NZ, [True] * NZ
    period = 1.0 / FRAME_RATE_HZ

    remote = RemoteEstimator(lc, chans, lockstep=False, expected_bank_hash=str(model_bank.content_hash),
                             initial_hypotheses=level0_hypotheses(model_bank))

    def echo_round_trip(t, u, z):
        nonlocal echo_lost
        due = remote.frame_due(t * FRAME_RATE_HZ + 0.5)
        while (wait := due - time.perf_counter()) > 0:
            time.sleep(wait)
        frame.frame = int(round(t * FRAME_RATE_HZ))
        frame.utime = int(round(t * 1e6))
        frame.z = [float(v) for v in z]
        data = frame.encode()
        state["got"] = False
        state["t_pub"] = time.perf_counter_ns()
        lc_echo.publish(ping, data)
        end = time.perf_counter() + 0.5 * period
        while not state["got"] and (left := end - time.perf_counter()) > 0:
            lc_echo.handle_timeout(max(1, int(left * 1000)))
        echo_lost += not state["got"]

    warm = (("--warm-lead-us", f"{warm_lead_us:g}") if warm_lead_us is not None else ()) + \
        (("--rewarm-us", f"{rewarm_us:g}") if rewarm_us is not None else ())
    daemon = DaemonProcess(path, lcm_url=lcm_url, channel_prefix=PREFIX, extra_args=(*rt, *warm),
                           cpus=server_cpus)
    try:
        t0 = time.perf_counter()
        result = fly_hil(scenario, model_bank, lc, chans, on_frame=echo_round_trip, remote=remote)
        wall = time.perf_counter() - t0
        lc_echo.unsubscribe(sub)
        sub = None
        p_ex, p_echo = paired_round_trips(lc, lc_echo, chans, ping, pong, model_bank, pairs, idle_ms / 1e3)
    finally:
        daemon.stop()
        echo.send_signal(2)
        echo_out = echo.communicate(timeout=5)[0]
        if sub is not None:
            lc_echo.unsubscribe(sub)
    link = result.timing["link"]
    ex = link["latency_us"]
    ec = _quantiles_us(echo_ns)
    echo_summary = [ln for ln in echo_out.splitlines() if ln.startswith("lcm-echo-f16:") and "statistics" not in ln]
    inside_ex = daemon.statistics["sensor_to_publish_us"]
    inside_echo = statistics_line(echo_out, "lcm-echo-f16")["message_to_publish_us"]
    return {
        "duration_s": duration_s, "wall_s": round(wall, 3), "rate_hz": FRAME_RATE_HZ, "lcm_url": lcm_url,
        "echo_lcm_url": echo_url,
        "bank": label, "bank_hash": str(model_bank.content_hash), "realtime_priority": realtime,
        "warm_lead_us": warm_lead_us, "rewarm_us": rewarm_us, "echo_wake_lead_us": echo_wake_lead_us,
        "echo_rewake_us": echo_rewake_us, "echo_work_us": echo_work_us,
        "placement": placement, "harness_cpus": sorted(os.sched_getaffinity(0)),
        "server_cpus": sorted(server_cpus) if server_cpus is not None else None,
        "frames": link["frames"], "deadline_misses": link["deadline_misses"],
        "executive_latency_us": {"n": link["statuses"], **ex},
        "echo_latency_us": ec, "echo_lost": echo_lost,
        "executive_excess_us": {k: (round(ex[k] - ec[k], 1) if ex[k] is not None and ec[k] is not None else None)
                                for k in ("p50", "p99")},
        "daemon_summary": daemon.summary, "echo_summary": echo_summary[-1] if echo_summary else "",
        "daemon_statistics": daemon.statistics,
        "inside_us": {"executive": inside_ex, "echo": inside_echo,
                      "excess": {k: (round(inside_ex[k] - inside_echo[k], 1)
                                     if inside_ex[k] is not None and inside_echo[k] is not None else None)
                                 for k in ("p50", "p99")}},
        "paired": {"pairs": pairs, "idle_ms": idle_ms, "executive_latency_us": _quantiles_us(p_ex),
                   "echo_latency_us": _quantiles_us(p_echo)},
        "host_floor_us": {f"{k:g}": v for k, v in floor.items()},
        "targets": {"deadline_misses": 0, "p99_excess_us_max": 20.0},
    }


PLACEMENTS = ("split", "shared", "free")


def place(placement: str) -> tuple[set[int] | None, set[int] | None]:
    """(CPUs of this process, CPUs of the daemon and the echo) for ``placement``; None: not
    pinned. With one usable CPU, split is shared."""
    if placement not in PLACEMENTS:
        raise ValueError(f"unknown placement {placement!r}; valid: {', '.join(PLACEMENTS)}")
    allowed = sorted(os.sched_getaffinity(0))
    if placement == "free":
        return None, None
    if placement == "shared" or len(allowed) == 1:
        return {allowed[-1]}, {allowed[-1]}
    return {allowed[0]}, {allowed[-1]}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    p = argparse.ArgumentParser(prog="f16mmae bench lcm",
                                description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--duration", type=float, default=60.0, metavar="S", help="flight length in s (default 60)")
    p.add_argument("--lcm-url", default=DEFAULT_URL, metavar="URL", help=f"LCM URL (default {DEFAULT_URL})")
    p.add_argument("--bank", default="tuned", metavar="tuned|untuned|FILE", help="bank (default tuned)")
    p.add_argument("--placement", default="free", choices=PLACEMENTS,
                   help="free (default): no pinning; split: this process (the harness) on the first CPU, "
                        "the daemon and the echo on the last -- the executive on a core of its own; "
                        "shared: all three on the last CPU")
    p.add_argument("--realtime", type=int, default=0, metavar="PRIORITY",
                   help="run the daemon, the echo and this process SCHED_FIFO at PRIORITY (root)")
    p.add_argument("--pairs", type=int, default=1000, metavar="N",
                   help="controlled pairing after the flight: N pairs (default 1000, 0: skip)")
    p.add_argument("--idle-ms", type=float, default=14.0, metavar="MS",
                   help="idle time before each paired round trip (default 14)")
    p.add_argument("--warm-lead-us", type=float, default=None, metavar="US",
                   help="the daemon's cache warm-up lead before each expected frame (default: the "
                        "daemon's, 500; 0: off)")
    p.add_argument("--rewarm-us", type=float, default=None, metavar="US",
                   help="after the first warm-up, the daemon warms up again every US until the frame "
                        "comes (default: the daemon's, 100; 0: once)")
    p.add_argument("--echo-wake-lead-us", type=float, default=0.0, metavar="US",
                   help="make the echo wake US before each expected ping, as the daemon does for its "
                        "warm-up, and do nothing: a control for the wake-up alone (default 0: a bare echo)")
    p.add_argument("--echo-rewake-us", type=float, default=0.0, metavar="US",
                   help="with --echo-wake-lead-us: wake again every US, as the daemon re-warms (default 0: once)")
    p.add_argument("--echo-work-us", type=float, default=0.0, metavar="US",
                   help="make the echo spend about US of register-only work before each reply, as the "
                        "executive spends its step (e.g. the daemon's step p50): a control for the time "
                        "spent in the callback, apart from the data the step touches (default 0)")
    p.add_argument("--json", default=None, metavar="FILE", help="also write the figures as JSON")
    args = p.parse_args(argv)
    if not args.duration > 0:
        p.error(f"--duration {args.duration} must be > 0")
    if not 0 <= args.realtime <= 99:
        p.error(f"--realtime {args.realtime} must be a priority from 1 to 99 (0: off)")
    if args.pairs < 0 or not args.idle_ms >= 0:
        p.error("--pairs must be >= 0 and --idle-ms >= 0")
    period_us = 1e6 / FRAME_RATE_HZ
    for opt, lead in (("--warm-lead-us", args.warm_lead_us), ("--echo-wake-lead-us", args.echo_wake_lead_us),
                      ("--rewarm-us", args.rewarm_us), ("--echo-rewake-us", args.echo_rewake_us),
                      ("--echo-work-us", args.echo_work_us)):
        if lead is not None and not 0 <= lead < period_us:
            p.error(f"{opt} {lead:g} must lie in [0, {period_us:g}) us (0: off; a frame lasts {period_us:g} us)")
    try:  # both round trips stay on the loopback of a namespace of their own
        status = reexec_in_private_netns([os.path.abspath(__file__), *argv])
    except NetnsError as e:
        p.error(str(e))
    if status is not None:
        return status
    r = run(args.duration, args.lcm_url, args.bank, args.realtime, args.pairs, args.idle_ms, args.warm_lead_us,
            args.echo_wake_lead_us, args.placement, args.rewarm_us, args.echo_rewake_us, args.echo_work_us)
    ex, ec, d = r["executive_latency_us"], r["echo_latency_us"], r["executive_excess_us"]
    rt = f", SCHED_FIFO {r['realtime_priority']}" if r["realtime_priority"] else ", time-shared"
    servers = "unpinned" if r["server_cpus"] is None else f"CPU {','.join(map(str, r['server_cpus']))}"
    rt += f"; harness on CPU {','.join(map(str, r['harness_cpus']))}, daemon and echo {servers}"
    print(f"LCM latency, {r['duration_s']:g} s at {r['rate_hz']} Hz on {r['lcm_url']} "
          f"({r['frames']} frames, wall {r['wall_s']} s{rt})")
    print(f"  {'':28s}{'p50 us':>10s}{'p99 us':>10s}{'max us':>10s}{'n':>8s}")
    print(f"  {'mmae-daemon sensor->status':28s}{ex['p50']:>10}{ex['p99']:>10}{ex['max']:>10}{ex['n']:>8}")
    echo_label = echo_name(r["echo_wake_lead_us"], r["echo_work_us"])
    print(f"  {echo_label:28s}{ec['p50']:>10}{ec['p99']:>10}{ec['max']:>10}{ec['n']:>8}")
    print(f"  {'executive - echo':28s}{d['p50']:>10}{d['p99']:>10}")
    ok_miss = r["deadline_misses"] == 0
    ok_p99 = d["p99"] is not None and d["p99"] <= 20.0
    print(f"  deadline misses: {r['deadline_misses']} (target 0: {'met' if ok_miss else 'MISSED'}); "
          f"p99 excess {d['p99']} us (target <= 20 us: {'met' if ok_p99 else 'MISSED'}); echo lost {r['echo_lost']}")
    if ec["p50"] and ec["p99"] > 3 * ec["p50"]:
        print(f"  note: the bare echo's own p99 is {ec['p99'] / ec['p50']:.0f}x its p50: this host's scheduling, "
              f"not the executive, sets both tails (compare the daemon's own step p99 below)")
    pe, pc = r["paired"]["executive_latency_us"], r["paired"]["echo_latency_us"]
    if pe["n"] and pc["n"]:
        print(f"  controlled pairing ({r['paired']['pairs']} pairs, {r['paired']['idle_ms']:g} ms idle before "
              f"each, order alternating):")
        print(f"  {'mmae-daemon sensor->status':28s}{pe['p50']:>10}{pe['p99']:>10}{pe['max']:>10}{pe['n']:>8}")
        print(f"  {echo_label:28s}{pc['p50']:>10}{pc['p99']:>10}{pc['max']:>10}{pc['n']:>8}")
        print(f"  {'executive - echo':28s}{pe['p50'] - pc['p50']:>10.1f}{pe['p99'] - pc['p99']:>10.1f}")
    ie, ic, ix = r["inside_us"]["executive"], r["inside_us"]["echo"], r["inside_us"]["excess"]
    if ix["p99"] is not None:
        print("  inside each process, message callback -> reply published (the executive's own share; "
              "no wake-up chain):")
        print(f"  {'mmae-daemon sensor-to-publish':28s}{ie['p50']:>10}{ie['p99']:>10}{ie['max']:>10}")
        print(f"  {'echo message-to-publish':28s}{ic['p50']:>10}{ic['p99']:>10}{ic['max']:>10}")
        print(f"  {'executive - echo':28s}{ix['p50']:>10}{ix['p99']:>10}")
    print(f"  {r['daemon_summary']}")
    print(f"  {r['echo_summary']}")
    floor = r["host_floor_us"]
    if len(floor) == 2:
        (_, b2b), (idle, after) = sorted(floor.items(), key=lambda kv: float(kv[0]))
        print(f"  host floor (f16mmae-idle-jitter: 5 us of register-only work, nothing to cache): back to back "
              f"p50 {b2b['p50']} / p99 {b2b['p99']} us; after {idle} us idle p50 {after['p50']} / p99 {after['p99']} us")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(r, f, indent=1)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
