"""``f16mmae replay LOGFILE``: recorded executive traffic through the in-process bank."""
from __future__ import annotations

import argparse
import math

import lcm

from ..banks import BankError, load_bank, turbulence_bank_set
from ..lcm.channels import channels
from ..lcm.daemon import daemon_flags
from ..lcm.replay import ReplayError, replay_log
from ..lcmt_mmae_status import lcmt_mmae_status
from ..loop.estimator_options import bank_defaults
from ..names import SHIPPED_TUNINGS, TURBULENCE_BANK
from .options import CliError, add_estimator_arguments, auth_from_option, estimator_options_from_args

DESCRIPTION = """\
Read an LCM log of executive traffic (recorded with the stock lcm-logger while
'f16mmae hil' flew against mmae-daemon), feed its sensor and command frames through the
daemon's own executive in process (its frame rules: duplicates and late frames dropped, lost
frames propagated without update, wild frame counters re-synchronised), and compare every logged status with the one computed
here: hypotheses on line, bank level, declaration, stale flag, probabilities and z_hat.
Exit status 0 when every status matches within the tolerance, 1 otherwise.

The estimator options (--threshold ... --actuator-limits) are those mmae-daemon ran with
(its ready line names them): give the same flags here, or the statuses differ.
"""

EXAMPLES = """\
examples:
  lcm-logger --channel 'F16_.*|MMAE_.*' run.lcmlog     # while 'f16mmae hil' flies
  f16mmae replay run.lcmlog
  f16mmae replay run.lcmlog --bank my.f16bank --channel-prefix SIM1_
  f16mmae replay run.lcmlog --adapt-turbulence --adapt-reference 1.0   # the daemon's own flags
  f16mmae replay run.lcmlog --bank turbulence --turbulence-banks       # a daemon that flew the set
  lcm-logplayer run.lcmlog                              # the same frames to a running daemon
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "replay", help="replay a recorded LCM log through the in-process bank and compare",
        description=DESCRIPTION, epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("logfile", metavar="LOGFILE", help="LCM event log (lcm-logger)")
    p.add_argument("--bank", default="auto", metavar="auto|tuned|untuned|scheduled|turbulence|FILE",
                   help="bank to replay with (default auto: the shipped bank whose hash the log's "
                        "statuses carry, else the turbulence bank set, flown as the set, when they carry "
                        "its hash)")
    p.add_argument("--channel-prefix", default="", metavar="P", help="prefix of the logged channel names")
    p.add_argument("--tolerance", default="1e-12", metavar="TOL",
                   help="largest accepted |probability difference| (default 1e-12)")
    p.add_argument("--auth-key", default=None, metavar="FILE",
                   help="use only the logged messages signed with the pre-shared key in FILE (as "
                        "mmae-daemon --auth-key FILE does); the others are skipped and counted")
    add_estimator_arguments(p)
    p.set_defaults(func=_replay)


def _bank_for(choice: str, logfile: str, prefix: str):
    if choice != "auto":
        try:
            return load_bank(choice)
        except BankError as exc:
            raise CliError(f"--bank: {exc}") from None
    hashes = _logged_bank_hashes(logfile, prefix)
    for tuning in SHIPPED_TUNINGS:
        try:
            label, path, bank = load_bank(tuning)
        except BankError:
            continue
        if str(bank.content_hash) in hashes:
            return label, path, bank
    try:
        if turbulence_bank_set().set_hash in hashes:   # mmae-daemon --turbulence-banks ran it
            return load_bank(TURBULENCE_BANK)
    except BankError:
        pass
    found = ", ".join(sorted(h[:12] for h in hashes)) or "none"
    raise CliError(f"--bank auto: no shipped bank ({', '.join(SHIPPED_TUNINGS)}) has the hash the log's "
                   f"statuses carry ({found}); give the bank file with --bank FILE")


def _logged_bank_hashes(logfile: str, prefix: str) -> set[str]:
    status = channels(prefix).status
    hashes: set[str] = set()
    log = lcm.EventLog(logfile, "r")
    try:
        for event in log:
            if event.channel == status:
                hashes.add(lcmt_mmae_status.decode(event.data).bank_hash)
                break  # one executive per log: its first status names the bank
    finally:
        log.close()
    return hashes


def _replay(args) -> int:
    try:
        tol = float(args.tolerance)
    except ValueError:
        raise CliError(f"--tolerance {args.tolerance!r} is not a number") from None
    if not (math.isfinite(tol) and tol >= 0):
        raise CliError(f"--tolerance {args.tolerance!r} must be finite and >= 0")
    auth = auth_from_option(args.auth_key)
    options = estimator_options_from_args(args)
    try:
        label, path, bank = _bank_for(args.bank, args.logfile, args.channel_prefix)
        if args.bank == "auto" and label == TURBULENCE_BANK:
            options["turbulence_banks"] = True   # the log's hash is the set's
        if options.get("adapt_turbulence") and not options.get("adapt_own_channels") and not options.get("turbulence_banks"):
            options["adapt_all_channels"] = True   # mmae-daemon's rule without --adapt-own-channels
        try:
            options = bank_defaults(options, bank)
        except ValueError as exc:   # an option left without the one it applies with
            raise CliError(str(exc)) from None
        report = replay_log(args.logfile, bank, channel_prefix=args.channel_prefix, tolerance=tol, auth=auth,
                             **options)
    except (ReplayError, OSError) as exc:
        raise CliError(str(exc)) from None
    print(f"replayed {args.logfile}: {report.events} events, {report.sensor_frames} sensor frames, "
          f"{report.command_frames} command frames, {report.statuses_logged} statuses; bank {label} "
          f"({str(bank.content_hash)[:12]})")
    print(f"estimator options: {' '.join(daemon_flags(options, bank.nu)) or 'none (the bank as designed)'}")
    if auth is not None:
        print(f"authenticated with {args.auth_key}: {report.unauthenticated} unauthenticated and "
              f"{report.replayed} replayed messages skipped")
    print(f"compared {report.statuses_compared} statuses: max |probability difference| "
          f"{report.max_probability_diff:.3g}, max |z_hat difference| {report.max_z_hat_diff:.3g} "
          f"(tolerance {tol:g})")
    for m in report.mismatches:
        print(f"  MISMATCH {m}")
    if report.mismatch_count > len(report.mismatches):
        print(f"  ... {report.mismatch_count - len(report.mismatches)} more")
    print("replay matches the log" if report.ok else f"replay DIFFERS from the log ({report.mismatch_count} mismatches)")
    return 0 if report.ok else 1
