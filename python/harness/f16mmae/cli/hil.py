"""``f16mmae hil``: fly the truth model against the MMAE executive (mmae-daemon) over LCM."""
from __future__ import annotations

import argparse
import math

import lcm
import numpy as np

from ..lcm.channels import HilError, channels, default_lcm_url
from ..lcm.daemon import DaemonProcess, daemon_flags
from ..lcm.hil import fly_hil
from ..loop.estimator_options import bank_defaults
from ..loop.flight import fly
from ..report.flight import write_flight
from .options import CliError, add_estimator_arguments, auth_from_option, estimator_options_from_args, number
from .run import add_flight_arguments, flight_from_args

DESCRIPTION = """\
Fly the nonlinear JSBSim F-16 here while the MMAE runs in mmae-daemon, over LCM, the way
the estimator sits beside a flight control computer: each frame the sensor frame goes
out on F16_SENSORS, the executive answers on MMAE_STATUS (probabilities, z_hat), the FCS
flies on z_hat (feedback mmae) and the commands go out on F16_COMMANDS.

--lockstep waits for every status (as fast as possible): the same scenario and seed give
the probabilities of the in-process 'f16mmae run' (to 1e-12; --compare checks it).
Without it the frames are paced in real time at 64 Hz and a status that misses its frame
is counted as a deadline miss (the FCS keeps the last z_hat). mmae-daemon is on PATH after
'pip install .'. Without --auth-key the daemon obeys any sender that reaches the LCM URL.
The estimator options (--threshold ... --schedule-mode) go to the daemon --start-daemon
starts and to the --compare run; a daemon of your own needs the same flags.
"""

EXAMPLES = """\
examples:
  f16mmae hil --start-daemon --lockstep --fail PIT@3     # one command: daemon started here
  mmae-daemon --bank BANK &                              # or a daemon of your own ...
  f16mmae hil --bank BANK --fail LS@3                    # ... flown in real time
  f16mmae hil --start-daemon --lockstep --compare        # check against the in-process run
  f16mmae hil --start-daemon --lockstep --compare --bank scheduled --adapt-turbulence \
      --trim-tracking 30 --mach 0.45 --alt-ft 22500       # the scheduled bank, adapting
  lcm-logger run.lcmlog & f16mmae hil --start-daemon     # record, then: f16mmae replay run.lcmlog
  head -c 32 /dev/urandom > link.key                     # authenticated frames: the same key
  mmae-daemon --bank BANK --auth-key link.key &          # for the daemon, hil and replay
  f16mmae hil --bank BANK --auth-key link.key

Latency benchmark (60 s at 64 Hz beside a bare C++ echo):
  f16mmae bench lcm --duration 60
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "hil", help="fly the truth model against mmae-daemon over LCM",
        description=DESCRIPTION, epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_flight_arguments(
        p, bank_help="the bank the executive runs (default tuned); checked against its status")
    add_estimator_arguments(p)
    p.add_argument("--lockstep", action="store_true",
                   help="wait for every status instead of pacing at 64 Hz real time")
    p.add_argument("--lcm-url", default=None, metavar="URL",
                   help="LCM URL (default $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0)")
    p.add_argument("--channel-prefix", default="", metavar="P", help="prefix of every channel name")
    p.add_argument("--start-daemon", action="store_true",
                   help="start mmae-daemon with --bank on this URL and stop it after the flight")
    p.add_argument("--timeout", default="5", metavar="S",
                   help="lockstep: how long to wait for one status (default 5 s)")
    p.add_argument("--compare", action="store_true",
                   help="also fly in process and report the largest probability difference")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="write run.json (with the link statistics), probabilities.csv/.png")
    p.add_argument("--auth-key", default=None, metavar="FILE",
                   help="sign every frame with the pre-shared key in FILE and use only statuses signed "
                        "with it (mmae-daemon --auth-key FILE; 16-64 bytes, e.g. head -c 32 /dev/urandom)")
    p.set_defaults(func=_hil)


def _hil(args) -> int:
    timeout_s = number("--timeout", args.timeout, minimum=0.0, exclusive=True, maximum=3600.0)
    label, path, bank, scenario = flight_from_args(args)
    # a scheduled bank's defaults as flags: mmae-daemon flies what the estimator in process does
    try:
        options = bank_defaults(estimator_options_from_args(args), bank)
    except ValueError as exc:   # an option left without the one it applies with
        raise CliError(str(exc)) from None
    url = args.lcm_url or default_lcm_url()
    if args.start_daemon and url.startswith("memq:"):
        raise CliError(f"--lcm-url {url!r} with --start-daemon: memq:// is a queue inside one "
                       f"process, which a daemon in another cannot reach; use a udpm:// URL "
                       f"(the default) or 'f16mmae run' for the estimator in process")
    chans = channels(args.channel_prefix)
    auth = auth_from_option(args.auth_key)
    try:
        lc = lcm.LCM(url)
    except RuntimeError as exc:
        raise CliError(f"--lcm-url {url!r} cannot be opened ({exc}); for udpm, multicast must work on "
                       f"this host (on loopback only: 'ip link set lo multicast on; "
                       f"ip route add 224.0.0.0/4 dev lo')") from None
    daemon = None
    try:
        if args.start_daemon:
            daemon = DaemonProcess(path, lcm_url=url, channel_prefix=args.channel_prefix, auth_key=args.auth_key,
                                   extra_args=daemon_flags(options, bank.nu))
            print(daemon.ready_line)
        elif options:  # no status carries the settings: say what the record assumes of that daemon
            print(f"estimator options: the record assumes the daemon on {url} runs with "
                  f"{' '.join(daemon_flags(options, bank.nu))} (see its ready line)")
        result = fly_hil(scenario, bank, lc, chans, lockstep=args.lockstep, timeout_s=timeout_s, auth=auth,
                         estimator_options=options)
    except HilError as exc:
        raise CliError(str(exc)) from None
    finally:
        if daemon is not None:
            daemon.stop()
            if daemon.summary:
                print(daemon.summary)

    s = result.scenario
    link = result.timing["link"]
    print(f"hil flight ({result.timing['mode']}): {s['duration_s']:g} s at Mach {s['mach']:g}, "
          f"{s['alt_ft']:.0f} ft, {s['turbulence']} turbulence, seed {s['seed']}, feedback {result.feedback}; "
          f"executive bank {label} ({result.bank_hash[:12]}) on {url} {chans.status}")
    inj = ", ".join(f"{f['name']} at {f['time_s']:g} s ({f['mode']})" for f in result.failures)
    print(f"injected: {inj or 'nothing'}")
    for d in result.declarations:
        what = "back-out to NONE" if d["hypothesis"] == "NONE" else f"declared {d['hypothesis']}"
        print(f"  {d['time_s']:7.3f} s  {what}")
    if not result.declarations:
        print("  no declaration")
    print(f"final hypothesis: {result.final_hypothesis}")
    lat = link["latency_us"]
    print(f"link: {link['frames']} frames, {link['statuses']} statuses, sensor->status latency p50 {lat['p50']} us, "
          f"p99 {lat['p99']} us, max {lat['max']} us; {link['deadline_misses']} deadline misses, "
          f"{link['stale_statuses']} stale")
    extra = {"link": link, "bank_file": str(path), "lcm_url": url, "channel_prefix": args.channel_prefix}
    if args.compare:
        local = fly(scenario, bank, estimator_options=options)
        same = local.hypotheses == result.hypotheses and local.probabilities.shape == result.probabilities.shape
        diff = float(np.nanmax(np.abs(local.probabilities - result.probabilities))) if same else math.inf
        print(f"in-process run: max |probability difference| = {diff:.3g} "
              f"({'identical declarations' if local.declarations == result.declarations else 'DECLARATIONS DIFFER'})")
        extra["in_process_max_probability_diff"] = diff
    if args.out:
        paths = write_flight(result, args.out, **extra)
        print(f"wrote {paths['run']}, {paths['csv'].name}, {paths['png'].name}")
    return 0
