"""``f16mmae campaign envelope``: the nominal design flown off its design point (paper Fig. 9)."""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..campaign.envelope import EnvelopeCampaign, figures, run_envelope
from ..campaign.envelope.points import PAPER_POINTS, EnvelopeError, check_distinct, parse_mach_alt, select_points
from ..report.evidence import describe_rate
from .campaign_common import (add_failure_instant, add_flight_settings, add_run_arguments, failure_instant, flight_settings,
                              parse_cases, run_and_report, validated)
from ..outputs import writable_dir
from .options import CliError

DESCRIPTION = """\
The off-nominal campaign (paper Sec. VIII, Fig. 9): the single-failure design (the bank,
designed at Mach 0.4, 20,000 ft, with its design trim) is kept as it is, while the truth
F-16 is trimmed and flown at flight-envelope points away from the design point; at each
point the exhaustive single-failure campaign (NONE + the twelve failures, N seeded runs
each, failure at 3.0 s of an 8-s flight) is run.  The estimator sees only u and z: the
model and trim mismatch off nominal is what is measured.  Run n of a case flies the same
seed at every point, so points differ by flight condition only.

A point is ACCEPTABLE when >= 90 % of its failure-case runs end with the injected failure
declared AND none of its runs (NONE runs included) has a false alarm (a failure declared
before the failure time, or at all in a NONE run).

Points (the paper's Fig. 9; q̄ = 0.7 p M^2, ISA, lbf/ft^2):
"""

EXAMPLES = """\
selections (--points): all = NOM + 1-24 (default), local = NOM + 1-20, extrema = NOM +
21-24, qline = 9,12,NOM,17,19 (the paper's axis of nearly constant q̄), or a comma list
such as 1,2,NOM, or random:N[:seed=S]: N Latin-hypercube points R1..RN over Mach
0.3-0.8 x 5,000-35,000 ft (seed S, default 1; a point that does not trim is redrawn
inside its cell).  --mach-alt MACH:ALT_FT,... adds custom points C1, C2, ... (alone
when --points is not given).

examples:
  f16mmae campaign envelope                          # 25 points x 13 cases x 2 runs
  f16mmae campaign envelope --points qline --runs 5
  f16mmae campaign envelope --points random:40:seed=3 --runs 10
  f16mmae campaign envelope --points local --cases NONE,LS,PIT,AZ
  f16mmae campaign envelope --mach-alt 0.42:21000,0.38:19000 --runs 3
  f16mmae campaign envelope --points NOM --mach-alt 0.5:25000 --tuning untuned
  f16mmae campaign envelope --compare results/env-nominal,results/env-scheduled --out results/env-compare

Output (DIR, default results/campaign-envelope):
  runs.jsonl          one record per run (point, seed, scenario with the point's Mach and
                      altitude, bank hash, version, declarations, outcome, latency)
  summary.json        per point: Mach, altitude, q̄, correct fraction, false-alarm runs,
                      median latency, acceptable, truth trim minus design trim, per-case counts
  envelope_map.png    the points on Mach-altitude axes coloured by correct fraction, with
                      lines of constant q̄ (the design point's bold)
  envelope_cases.png  correct runs per point (rows, by q̄) and case (columns)
  report.html         all of it on one self-contained page
Resume: run the same command again -- runs already in DIR/runs.jsonl are skipped.
"""


def _point_table() -> str:
    rows = [f"  {'point':>5} {'group':<8} {'Mach':>6} {'alt ft':>7} {'q̄':>7}"]
    rows += [f"  {p.label:>5} {p.group:<8} {p.mach:>6.3f} {p.alt_ft:>7.0f} {p.qbar_psf:>7.1f}"
             for p in PAPER_POINTS]
    return "\n".join(rows) + "\n"


def register(kinds) -> None:
    """Add the ``envelope`` parser to the ``campaign`` kinds."""
    e = kinds.add_parser(
        "envelope",
        help="the nominal design flown at off-nominal Mach/altitude points (paper Fig. 9)",
        description=DESCRIPTION + _point_table(),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_flight_settings(e, "2", "seeded runs per case and point (default 2)")
    e.add_argument("--points", default=None, metavar="SEL",
                   help="all | local | extrema | qline | comma list of 1-24 and NOM | random:N[:seed=S] "
                        "(default all)")
    e.add_argument("--mach-alt", default=None, metavar="M:H,...",
                   help="custom points MACH:ALT_FT (e.g. 0.42:21000), Mach 0.3-0.8, 5,000-35,000 ft")
    e.add_argument("--cases", default=None, metavar="LIST",
                   help="comma-separated cases (default: NONE and all twelve failures)")
    e.add_argument("--compare", default=None, metavar="DIR_A,DIR_B",
                   help="fly nothing: draw the maps of two (or more) finished envelope campaigns side by side "
                        "(e.g. unscheduled and scheduled bank) into OUT/envelope_compare.png")
    add_failure_instant(e)
    add_run_arguments(e, "results/campaign-envelope")
    e.set_defaults(func=_envelope)


def points_from_args(args):
    """The points of ``--points`` and ``--mach-alt`` (CliError naming bad values)."""
    try:
        custom = parse_mach_alt(args.mach_alt) if args.mach_alt is not None else ()
        if args.points is None:
            paper = () if custom else select_points("all")
        else:
            paper = select_points(args.points)
        points = tuple(paper) + tuple(custom)
        check_distinct(points)
    except EnvelopeError as exc:
        raise CliError(str(exc)) from None
    return points


def config_from_args(args) -> EnvelopeCampaign:
    """A validated ``EnvelopeCampaign`` from the parsed arguments (CliError otherwise)."""
    cfg = EnvelopeCampaign(**flight_settings(args), **failure_instant(args), points=points_from_args(args),
                           cases=parse_cases(args.cases))
    return validated(cfg)


def compare(dirs_text: str, out: str) -> Path:
    """``--compare``: the side-by-side map of finished envelope campaigns (CliError naming a
    directory without an envelope summary); the output directory is checked first."""
    dirs = [Path(d.strip()) for d in dirs_text.split(",") if d.strip()]
    if len(dirs) < 2:
        raise CliError(f"--compare {dirs_text!r}: give two or more campaign directories DIR_A,DIR_B")
    out_dir = writable_dir(out)
    summaries = []
    for d in dirs:
        try:
            s = json.loads((d / "summary.json").read_text())
        except (OSError, ValueError) as exc:
            raise CliError(f"--compare: {d}/summary.json cannot be read ({exc})") from None
        if s.get("kind") != "envelope":
            raise CliError(f"--compare: {d}/summary.json is of kind {s.get('kind')!r}, not 'envelope'")
        summaries.append(s)
    return figures.compare_maps(summaries, Path(out_dir) / figures.COMPARE_FILE)


def _envelope(args) -> int:
    if args.compare is not None:
        print(f"wrote {compare(args.compare, args.out)}")
        return 0
    return run_and_report(args, config_from_args(args), run_envelope, print_summary)


def print_summary(summary: dict, stream) -> None:
    d = summary["design_point"]
    rule = summary["acceptable_rule"]
    t = summary.get("timing", {})
    print(f"envelope campaign: {summary['tuning']} bank designed at Mach {d['mach']:g}, "
          f"{d['alt_ft']:.0f} ft (q̄ {d['qbar_psf']:.1f} lbf/ft^2); {summary['runs_per_case']} run(s) x "
          f"{len(summary['cases'])} cases per point, seed {summary['seed']}, {summary['turbulence']} "
          f"turbulence; wall {t.get('wall_s', 0):.1f} s", file=stream)
    print(f"\n  {'point':>5} {'Mach':>6} {'alt ft':>7} {'q̄':>6} {'correct [95% CI]':>17} {'FA':>3} {'TW':>3} "
          f"{'lat med':>7}  acceptable  verdict", file=stream)
    for p in summary["points"]:
        rates = p["evidence"]["rates"]
        corr = describe_rate(rates.get("correct"))
        lat = "-" if p["latency_median_s"] is None else f"{p['latency_median_s']:.2f}"
        print(f"  {p['label']:>5} {p['mach']:>6.3f} {p['alt_ft']:>7.0f} {p['qbar_psf']:>6.1f} "
              f"{corr:>17} {p['false_alarm_runs']:>3} {rates['transient_wrong']['count']:>3} {lat:>7}  "
              f"{'yes' if p['acceptable'] else 'NO':<10}  {p['evidence']['verdict']}",
              file=stream)
    ok = [p["label"] for p in summary["points"] if p["acceptable"]]
    print(f"\nacceptable (>= {rule['correct_fraction_min']:.0%} of failure runs correct, "
          f"<= {rule['false_alarm_runs_max']} false-alarm runs): {len(ok)}/{len(summary['points'])} "
          f"points{': ' + ', '.join(ok) if ok else ''}", file=stream)
