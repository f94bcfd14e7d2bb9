"""A calm-air / light-turbulence bank pair selected on line by the calm bank's own intensity
measure rho: does it keep both banks' strengths?  A prototype measured in closed loop, not a
product estimator (issue 13 item 4).

Both banks (two throttle banks, ``f16mmae design --throttle-input [--gust-level none]``) run
on every frame on the same z, u and air data.  rho is the calm bank's turbulence-adaptation
measure (cpp/f16mmae/turbulence_adaptation.h: the average over 5 s of min_k q_k / nz; its
scale held at 1, so the calm bank flies as designed).  The light bank is in force for the
first ``--settle`` seconds and whenever rho >= ``--switch-rho``; the calm bank otherwise; no
switch while the bank in force declares a failure (a failure raises the residual power too:
without this hold, rho hovering at the threshold after a calm-air AOA failure switched one
flight back and forth 15 times, reporting a back-out to NONE on the way).  What
the loop sees (z_hat for the FCS, probabilities, declarations) is the bank in force; on a switch
its current hypothesis is reported as a declaration when it differs from the last one reported
(or when the hypotheses on line differ).  The threshold comes from tools/turbulence_rho.py on
its own seeds (campaign seed 7): calm air 0.576-0.636, light turbulence 0.653-3.03 over
1-8 s.

The flights are the single-failure campaign's (``evaluation_seed("single", S, case, run)``,
the failure at 3 s of 8 s, feedback mmae), so the table compares directly with
``f16mmae campaign single --seed S`` of either bank.  Scoring as tools/excitation/excitation_offline.py:
correct = the failure is the first declaration at or after 3 s and nothing but NONE before it;
NONE: nothing but NONE declared.

    .venv/bin/python tools/excitation/bank_pair.py --calm CALM.f16bank --light LIGHT.f16bank --runs 20
"""
from __future__ import annotations

import argparse

from excitation_offline import describe, print_summary

from f16mmae.banks import load_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.flight import fly
from f16mmae.names import FAILURE_TIME_S, FLIGHT_S, FRAME_RATE_HZ, NONE, SINGLE_HYPOTHESES
from f16mmae.seeds import evaluation_seed
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure


class PairedEstimator:
    """The loop's estimator interface (loop/flight.py ``fly(estimator=...)``) over a bank pair
    (module docstring)."""

    def __init__(self, calm, light, switch_rho: float, settle_s: float):
        self.calm = Estimator(calm, adapt_turbulence=True, adapt_scale_max=1.0)
        self.light = Estimator(light)
        self.switch_rho, self.settle_frames = switch_rho, int(round(settle_s * FRAME_RATE_HZ))
        self.selected, self.frames, self.switches = self.light, 0, 0
        self.bank_hash = f"{light.content_hash}+{calm.content_hash}"
        self.last_declaration: str | None = None
        self._reported = NONE
        self.calm_frames = 0

    def schedule(self, mach, pressure_altitude_ft) -> None:
        self.calm.schedule(mach, pressure_altitude_ft)
        self.light.schedule(mach, pressure_altitude_ft)

    def update(self, z):
        z_hat = {"calm": self.calm.update(z), "light": self.light.update(z)}
        self.frames += 1
        rho = self.calm.core_bank.turbulence_power_ratio
        want = self.calm if self.frames > self.settle_frames and rho < self.switch_rho else self.light
        if self.selected.declared != NONE:
            want = self.selected  # hold the bank that declared a failure
        before = self.selected.hypotheses
        switched = want is not self.selected
        if switched:
            self.selected, self.switches = want, self.switches + 1
        self.calm_frames += self.selected is self.calm
        d = self.selected.last_declaration
        if d is None and switched and (self.selected.declared != self._reported or self.selected.hypotheses != before):
            d = self.selected.declared
        if d is not None:
            self._reported = d
        self.last_declaration = d
        return z_hat["calm" if self.selected is self.calm else "light"]

    def propagate(self, u) -> None:
        self.calm.propagate(u)
        self.light.propagate(u)

    @property
    def hypotheses(self):
        return self.selected.hypotheses

    @property
    def probabilities(self):
        return self.selected.probabilities

    @property
    def declared(self) -> str:
        return self.selected.declared


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--calm", required=True, help="bank designed for calm air (--gust-level none)")
    p.add_argument("--light", required=True, help="bank designed for light turbulence")
    p.add_argument("--switch-rho", type=float, default=0.645)
    p.add_argument("--settle", type=float, default=1.0, help="seconds on the light bank at the start")
    p.add_argument("--levels", default="none,light")
    p.add_argument("--cases", default=",".join(SINGLE_HYPOTHESES))
    p.add_argument("--runs", type=int, default=10)
    p.add_argument("--seed", type=int, default=1, help="campaign seed S (evaluation seeds of campaign single)")
    args = p.parse_args(argv)
    calm, light = load_bank(args.calm)[2], load_bank(args.light)[2]
    summary, columns = {}, []
    for level in args.levels.split(","):
        columns.append(f"pair, {level}")
        share = []
        for case in args.cases.split(","):
            for n in range(args.runs):
                fails = () if case == NONE else (make_failure(case, FAILURE_TIME_S, "complete"),)
                sc = Scenario(turbulence=level, duration_s=FLIGHT_S, seed=evaluation_seed("single", args.seed, case, n),
                              feedback="mmae", failures=fails)
                est = PairedEstimator(calm, light, args.switch_rho, args.settle)
                r = fly(sc, light, estimator=est, record_probabilities=True)
                decl = [(d["time_s"], d["hypothesis"]) for d in r.declarations]
                summary.setdefault((case, len(columns) - 1), []).append(describe(decl, case))
                share.append(est.calm_frames / est.frames)
        print(f"{level}: calm bank in force {100 * sum(share) / len(share):.1f} % of the frames "
              f"(min {100 * min(share):.1f} %, max {100 * max(share):.1f} %)", flush=True)
    print_summary(summary, columns)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
