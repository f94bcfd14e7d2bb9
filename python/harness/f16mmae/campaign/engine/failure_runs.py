"""Single-failure runs at one flight condition: plan them and fly one.

The single-failure campaign flies them at the bank's design point; the off-nominal
(envelope) campaign flies the same plan at each of its points.  Cases: the no-failure case
NONE and each of the twelve single failures, ``runs`` seeded runs each, the failure (in the
config's ``mode``) at ``failure_time_s``.

Seeds: run n of case c gets ``seed_{c,n} = evaluation_seed("single", S, c, n)`` with S the
campaign seed (``f16mmae.seeds``: ``1 + (SHA-256("evaluation:single:S:c:n") mod (2^31 - 2))``,
re-drawn in the rare case it is a tuning seed) -- deterministic, >= 1, never a seed the
tuning flew, independent of the executor, of the order runs finish, of the bank and of the flight condition (runs of one
(c, n) fly the same turbulence and noise with any bank, at any point: common random numbers).

Failure offset (``failure_jitter_s`` J > 0 on the config; 0, the default: none): run n of case c
fails at ``failure_time_s + J x_{c,n}`` and flies ``duration_s + J x_{c,n}``, the same time after
its failure as without, where x_{c,n} = SHA-256("failure-offset:<seed_{c,n}>") / 2^256 in [0, 1),
a pure function of the run's seed. Why: the surfaces' dither is deterministic, so every run of a
case failing at the same instant meets the same dither phase; a failed surface frozen at trim steps
from wherever its dither had it, and which hypotheses that step lifts depends on the phase
(docs/results/turbulence_banks.md, round 19). J of a dither period or more samples the phases.

Each run is a pure function of its spec (:func:`run_spec`), executed on any
``concurrent.futures.Executor``.
"""
from __future__ import annotations

import hashlib

from ... import __version__
from ...loop.flight import fly, scenario_from_dict
from ...names import NONE, SINGLE_HYPOTHESES
from . import outcomes, scoring
from .config import CampaignError
from .rounding import decimal_round
from .runner import planned_bank
from .seeds import evaluation_seed
from .store import run_key

#: Cases of a single-failure plan, in the paper's order.
CASES: tuple[str, ...] = SINGLE_HYPOTHESES
#: How often the stored probability history of the injected hypothesis is sampled.
P_INJECTED_DECIMATION = 2  # every 2nd frame: 32 Hz at the 64-Hz frame rate


def stored_history(p) -> list[float]:
    """A probability history as a record stores it: every ``P_INJECTED_DECIMATION``-th frame,
    each value ``round(float(x), 5)`` (``rounding.decimal_round``, bit for bit)."""
    return decimal_round(p[::P_INJECTED_DECIMATION], 5)


#: Largest failure jitter a campaign takes (s): a minute covers every dither line's period,
#: the throttle's 10 s included.
FAILURE_JITTER_S_MAX = 60.0


def check_failure_jitter(cfg) -> None:
    """CampaignError unless ``cfg.failure_jitter_s`` lies in [0, FAILURE_JITTER_S_MAX]."""
    if not 0.0 <= cfg.failure_jitter_s <= FAILURE_JITTER_S_MAX:
        raise CampaignError(f"--failure-jitter {cfg.failure_jitter_s:g} must lie in [0, {FAILURE_JITTER_S_MAX:g}] s")


def failure_offset(seed: int, jitter_s: float) -> float:
    """The run's failure offset J x in [0, J) s (module docstring), 0 when ``jitter_s`` is 0."""
    if not jitter_s:
        return 0.0
    x = int.from_bytes(hashlib.sha256(f"failure-offset:{seed}".encode()).digest(), "big") / 2.0 ** 256
    return float(jitter_s) * x


def run_seed(campaign_seed: int, case: str, run_index: int) -> int:
    """The seed of run ``run_index`` of ``case`` (>= 1), see the module docstring."""
    return evaluation_seed("single", campaign_seed, case, run_index)


def check_cases(cfg) -> None:
    """CampaignError unless ``cfg.cases`` are known, distinct and not empty and
    ``cfg.failure_time_s`` lies inside the flight."""
    bad = [c for c in cfg.cases if c not in CASES]
    if bad or not cfg.cases:
        raise CampaignError(
            f"unknown case(s) {', '.join(bad) or '(none given)'}; valid: {', '.join(CASES)}"
        )
    if len(set(cfg.cases)) != len(cfg.cases):
        raise CampaignError(f"a case is listed twice in {','.join(cfg.cases)}")
    if not 0 < cfg.failure_time_s < cfg.duration_s:
        raise CampaignError(
            f"the failure time {cfg.failure_time_s} s must lie inside the flight (0, {cfg.duration_s}) s"
        )


def check_case_failures(cfg) -> None:
    """:func:`check_cases`, and CampaignError unless every failure case's component takes the
    config's (one) failure mode."""
    check_cases(cfg)
    for case in cfg.cases:
        if case != NONE:
            try:
                cfg.failure(case, cfg.failure_time_s)
            except ValueError as exc:
                raise CampaignError(f"case {case}: {exc}") from None


# -- one run (executed in workers) -----------------------------------------------------------
def run_spec(spec: dict) -> dict:
    """Fly one run and return its record (without the store's bookkeeping).

    A pure function of ``spec``: the scenario (seeded), the bank (checked against the
    spec's hash) and the estimator settings."""
    bank = planned_bank(spec)
    scenario = scenario_from_dict(spec["scenario"])
    result = fly(scenario, bank, estimator_options=spec["estimator"], record_probabilities=True)
    case = spec["case"]
    failure_time = scenario.failures[0].time_s if case != NONE else None
    declarations = scoring.isolating_declarations(result.declarations)   # partial hypotheses: their surface
    scored = scoring.score_run(case, failure_time, declarations)
    return {
        "run_key": spec["run_key"],
        "kind": "single",
        "case": case,
        "run_index": spec["run_index"],
        "seed": spec["seed"],
        "tuning": spec["tuning"],
        "bank": spec["bank"],  # the --tuning / --bank argument that names the bank
        "bank_hash": spec["bank_hash"],
        "version": spec["version"],
        "scenario": spec["scenario"],
        "estimator": spec["estimator"],
        "estimator_settings": result.estimator_settings,  # in force: bank's recommended + overrides
        "failure_time_s": failure_time,
        "failures": result.failures,
        "declarations": declarations,
        **({"declared_hypotheses": [d["hypothesis"] for d in result.declarations]}
           if declarations != list(result.declarations) else {}),
        **scored,
        **outcomes.run_fields(declarations, failure_time, {case}, scenario.duration_s),
        "p_injected": stored_history(result.probability_of(case)),
        "p_injected_dt_s": P_INJECTED_DECIMATION * result.frame_dt_s,
        "timing": result.timing,
    }


def describe_spec(spec: dict) -> str:
    """The run a spec stands for, for messages."""
    return f"run {spec['run_index']} of case {spec['case']} ({spec['tuning']} bank, seed {spec['seed']})"


# -- planning --------------------------------------------------------------------------------
def plan(cfg, banks: dict[str, tuple[str, object]], mach: float | None = None,
         alt_ft: float | None = None) -> list[dict]:
    """Every run spec of ``cfg`` (a config with ``cases``, ``failure_time_s`` and
    ``failure_jitter_s``: module docstring) at the flight
    condition (``mach``, ``alt_ft``; None: each bank's design point). ``banks`` maps
    label -> (tuning arg, ModelBank)."""
    specs = []
    for label, (tuning_arg, bank) in banks.items():
        for case in cfg.cases:
            for n in range(cfg.runs):
                seed = run_seed(cfg.seed, case, n)
                offset = failure_offset(seed, cfg.failure_jitter_s)
                failures = () if case == NONE else ((case, cfg.failure_time_s + offset),)
                try:
                    scenario = cfg.scenario_dict(bank, failures, seed, mach, alt_ft,
                                                 duration_s=cfg.duration_s + offset)
                except ValueError as exc:
                    raise CampaignError(f"case {case}: {exc}") from None
                identity = {"kind": "single", "scenario": scenario, "estimator": cfg.estimator_options(),
                            "bank_hash": bank.content_hash, "version": __version__}
                specs.append({
                    "run_key": run_key(identity), "case": case, "run_index": n, "seed": seed,
                    "tuning": label, "bank": tuning_arg, "bank_hash": bank.content_hash,
                    "version": __version__, "scenario": scenario, "estimator": cfg.estimator_options(),
                })
    return specs
