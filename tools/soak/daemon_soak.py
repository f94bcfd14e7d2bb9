"""The daemon soak: hours of 64-Hz frames through ``mmae-daemon`` over udpm, in lockstep,
against the same executive in process (``core.Executive``), in minutes.

    python tools/soak/daemon_soak.py [--hours 1] [--bank tuned] [--seed 1] [--json FILE]

Runs itself inside a private network namespace (``unshare --user --map-root-user --net``,
loopback with multicast): no packet leaves the host. The frames are synthetic and seeded:
z = z_trim + white noise (sigma 0.2 % of each channel's trim magnitude, at least 1e-3) with a
bias on one sensor for one minute in every ten (the failure cycles through the seven sensors,
so the bank declares, goes to level 1 and backs out), u = u_trim + noise; and on the wire,
every 997th sensor frame is sent twice, every 4999th carries a NaN. For every sensor frame
it compares the daemon's status with the in-process one, field by field (all but the step
time and the auth trailer): probabilities, z_hat, declarations, levels, flags and counters
must be identical. It samples the daemon's resident memory (VmRSS) once a simulated minute,
and at the end checks the daemon's statistics line against the counts it sent. Prints a
summary (and writes it as JSON with --json); exit status 0 when everything held.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

from f16mmae.lcm.netns import NetnsError, reexec_in_private_netns

URL = "udpm://239.255.76.67:7690?ttl=0"
COMPARED = ("frame", "utime", "bank_hash", "bank_level", "level_failure", "declared", "declaration",
            "num_hypotheses", "hypothesis_names", "probabilities", "z_hat", "stale", "frames_without_update",
            "frames_updated", "frames_rejected", "frames_dropped", "frames_stale", "commands_missed",
            "resynchronised", "frames_resynchronised")


def rss_kib(pid: int) -> int:
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


def soak(hours: float, bank_choice: str, seed: int) -> dict:
    import lcm
    import numpy as np

    from f16mmae import core
    from f16mmae.banks import bank_estimator_settings, load_bank
    from f16mmae.lcm.channels import channels
    from f16mmae.lcm.codec import command_frame_bytes, frame_utime, sensor_frame_bytes
    from f16mmae.lcm.daemon import DaemonProcess
    from f16mmae.lcmt_mmae_status import lcmt_mmae_status
    from f16mmae.names import FRAME_RATE_HZ

    label, path, bank = load_bank(bank_choice)
    frames = int(round(hours * 3600 * FRAME_RATE_HZ))
    rng = np.random.default_rng(seed)
    z_trim, u_trim = np.array(bank.z_trim), np.array(bank.u_trim)
    z_sigma = np.maximum(2e-3 * np.abs(z_trim), 1e-3)
    minute = int(60 * FRAME_RATE_HZ)
    executive = core.Executive(bank, **bank_estimator_settings(bank))
    chans = channels("SOAK_")
    lc = lcm.LCM(URL)
    got: dict[int, bytes] = {}
    lc.subscribe(chans.status, lambda ch, data: got.__setitem__(lcmt_mmae_status.decode(data).frame, data))
    sent = {"sensor": 0, "command": 0, "duplicate": 0, "nan": 0}
    mismatches, rss, levels, declarations = [], [], set(), 0
    t0 = time.perf_counter()
    with DaemonProcess(path, lcm_url=URL, channel_prefix="SOAK_") as daemon:
        rss.append((0, rss_kib(daemon.pid)))
        for i in range(frames):
            z = z_trim + z_sigma * rng.standard_normal(7)
            if (i // minute) % 10 == 5:  # one minute in ten: a bias on one sensor
                k = (i // (10 * minute)) % 7
                z[k] += 40 * z_sigma[k]
            u = u_trim + 1e-3 * rng.standard_normal(5)
            nan = i % 4999 == 4998
            if nan:
                z[2] = float("nan")
                sent["nan"] += 1
            data = sensor_frame_bytes(i, z)
            lc.publish(chans.sensors, data)
            sent["sensor"] += 1
            fate = executive.on_sensor(i, z, utime=frame_utime(i))
            if i % 997 == 996:
                lc.publish(chans.sensors, data)
                sent["duplicate"] += 1
                executive.on_sensor(i, z, utime=frame_utime(i))
            if fate in ("used", "resynchronised"):
                end = time.monotonic() + 5.0
                while i not in got and time.monotonic() < end:
                    lc.handle_timeout(50)
                mine = lcmt_mmae_status.decode(executive.encoded_status)
                theirs = lcmt_mmae_status.decode(got.pop(i)) if i in got else None
                if theirs is None:
                    mismatches.append(f"frame {i}: no status from the daemon within 5 s")
                else:
                    for name in COMPARED:
                        a, b = getattr(theirs, name), getattr(mine, name)
                        if (list(a) if isinstance(a, (list, tuple)) else a) != \
                                (list(b) if isinstance(b, (list, tuple)) else b):
                            mismatches.append(f"frame {i}: {name} differs")
                            break
                levels.add(mine.bank_level)
                declarations += bool(mine.declaration)
            lc.publish(chans.commands, command_frame_bytes(i, u))
            sent["command"] += 1
            executive.on_command(i, u, utime=frame_utime(i))
            if i % minute == minute - 1:
                rss.append(((i + 1) // minute, rss_kib(daemon.pid)))
            if len(mismatches) > 20:
                break
        time.sleep(0.5)
    wall = time.perf_counter() - t0
    m = daemon.statistics["messages"]
    expected = {"received": sent["sensor"] + sent["duplicate"] + sent["command"],
                "used": sent["sensor"] - sent["nan"] + sent["command"],
                "duplicate": sent["duplicate"], "rejected": sent["nan"], "out_of_order": 0,
                "resynchronised": 0, "undecodable": 0, "unauthenticated": 0, "replayed": 0}
    counters_exact = all(m[k] == v for k, v in expected.items())
    rss_kib_values = [r for _, r in rss]
    after_first = rss_kib_values[1:] or rss_kib_values
    return {
        "command": " ".join(["python", "tools/soak/daemon_soak.py", *sys.argv[1:]]),
        "bank": label, "bank_hash": str(bank.content_hash), "hours": hours, "frames": frames, "seed": seed,
        "wall_s": round(wall, 1), "frames_per_s": round(frames / wall, 1),
        "statuses_identical": not mismatches, "mismatches": mismatches[:20],
        "levels_seen": sorted(levels), "declarations": declarations,
        "sent": sent, "daemon_messages": m, "expected_messages": expected, "counters_exact": counters_exact,
        "rss_kib": {"start": rss_kib_values[0], "after_1_min": after_first[0], "end": rss_kib_values[-1],
                    "max_after_1_min": max(after_first), "samples": len(rss_kib_values)},
        "daemon_step_us": daemon.statistics["step_us"],
        "ok": not mismatches and counters_exact and max(after_first) - after_first[0] <= 256,
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--hours", type=float, default=1.0, help="simulated hours of 64-Hz frames (default 1)")
    p.add_argument("--bank", default="tuned", help="tuned, untuned or a bank file (default tuned)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", default=None, metavar="FILE")
    args = p.parse_args(argv)
    if not 0 < args.hours <= 24:
        p.error(f"--hours {args.hours:g} must lie in (0, 24]")
    try:
        status = reexec_in_private_netns([os.path.abspath(__file__), *(argv if argv is not None else sys.argv[1:])])
    except NetnsError as e:
        p.error(str(e))
    if status is not None:
        return status
    r = soak(args.hours, args.bank, args.seed)
    print(f"daemon soak: {r['frames']} frames ({r['hours']:g} h at 64 Hz) in {r['wall_s']} s "
          f"({r['frames_per_s']} frames/s), bank {r['bank']} ({r['bank_hash'][:12]})")
    print(f"  statuses identical to in-process: {r['statuses_identical']} (levels {r['levels_seen']}, "
          f"{r['declarations']} declarations)")
    print(f"  counters exact: {r['counters_exact']} (daemon {json.dumps(r['daemon_messages'])})")
    q = r["rss_kib"]
    print(f"  daemon RSS: {q['start']} KiB at start, {q['after_1_min']} KiB after 1 min, {q['end']} KiB at the end "
          f"(max after 1 min {q['max_after_1_min']} KiB, {q['samples']} samples)")
    s = r["daemon_step_us"]
    print(f"  daemon step: p50 {s['p50']} us, p99 {s['p99']} us, max {s['max']} us over {s['count']} frames")
    for m in r["mismatches"]:
        print(f"  MISMATCH {m}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(r, f, indent=1)
            f.write("\n")
    print("soak OK" if r["ok"] else "soak FAILED")
    return 0 if r["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
