"""What every campaign kind is configured by: the flight settings they share, once.

A kind's config (``SingleCampaign``, ``DualCampaign``, ``EnvelopeCampaign``) is a frozen
dataclass derived from :class:`CampaignConfig`; it adds what is its own (cases, pairs,
points, failure times) and may change a shared field's default (runs, duration).
:meth:`CampaignConfig.check_common` checks the shared fields; each kind's ``validate``
calls it and checks its own.  Every check raises :class:`CampaignError` naming the bad
value and the valid range.
"""
from __future__ import annotations

from dataclasses import dataclass

from ...errors import F16mmaeError
from ...names import (DWELL_S_MAX, ESTIMATOR_SETTINGS, FEEDBACK_MODES, FLIGHT_S, SINGLE_HYPOTHESES,
                      TURBULENCE_LEVELS)
from ...truth import DitherSpec, Scenario
from ...truth.failures import FailureSpec, make_failure


#: The most seeded runs per case (or pair, or point and case) a campaign plans.
RUNS_MAX = 1000
#: The largest multiple of the truth model's default dither amplitudes a campaign flies.
DITHER_SCALE_MAX = 5.0


class CampaignError(F16mmaeError):
    """A campaign argument is invalid, or a run failed; the message names it."""


def scaled_dither(enabled: bool, scale: float = 1.0) -> DitherSpec:
    """The truth model's default dither, on or off, its amplitudes multiplied by ``scale``
    (``f16mmae run --dither-scale`` flies what a campaign's ``--dither-scale`` does)."""
    base = DitherSpec(enabled=enabled)
    if scale == 1.0:
        return base
    return DitherSpec(enabled=enabled, amplitude_deg=tuple(a * scale for a in base.amplitude_deg),
                      frequency_hz=base.frequency_hz, phase_rad=base.phase_rad)


@dataclass(frozen=True)
class CampaignConfig:
    """The flight settings every campaign kind shares (everything that shapes its runs)."""

    runs: int = 10
    seed: int = 1
    tuning: str = "tuned"  # "tuned" | "untuned" | path to a bank file
    turbulence: str = "light"
    mode: str = "complete"
    duration_s: float = FLIGHT_S
    feedback: str = "mmae"
    dither: bool = True
    dither_scale: float = 1.0  # multiplies the truth model's default dither amplitudes
    #: Estimator settings passed to core.HierarchicalBank (None: the bank's recommended):
    #: declaration threshold, dwell (s) and probability floor p_min.
    threshold: float | None = None
    dwell_s: float | None = None
    p_min: float | None = None

    def estimator_options(self) -> dict:
        """The estimator settings this config overrides (unset ones stay the bank's recommended)."""
        return {k: getattr(self, k) for k in ESTIMATOR_SETTINGS if getattr(self, k) is not None}

    def dither_spec(self) -> DitherSpec:
        """The truth model's dither for this config (its ``dither`` switch and ``dither_scale``)."""
        return scaled_dither(self.dither, self.dither_scale)

    def check_common(self, dwell_window_s: float, dwell_window_text: str = "") -> None:
        """The checks of the shared fields (CampaignError naming the bad value): runs, seed,
        turbulence, feedback, dither scale and the estimator overrides; the dwell must fit in
        ``dwell_window_s``, the flight time in which a declaration can still come."""
        if not 1 <= self.runs <= RUNS_MAX:
            raise CampaignError(f"--runs must lie in [1, {RUNS_MAX}], got {self.runs}")
        if self.seed < 1:
            raise CampaignError(f"--seed must be >= 1 (JSBSim treats 0 as 1), got {self.seed}")
        if self.turbulence not in TURBULENCE_LEVELS:
            raise CampaignError(f"unknown turbulence {self.turbulence!r}; valid: {', '.join(TURBULENCE_LEVELS)}")
        if self.feedback not in FEEDBACK_MODES:
            raise CampaignError(f"unknown feedback {self.feedback!r}; valid: {', '.join(FEEDBACK_MODES)}")
        if not 0.0 <= self.dither_scale <= DITHER_SCALE_MAX:
            raise CampaignError(f"--dither-scale {self.dither_scale} must lie in [0, {DITHER_SCALE_MAX}]")
        if self.threshold is not None and not 0.5 < self.threshold < 1.0:
            raise CampaignError(f"--threshold {self.threshold} must lie in (0.5, 1)")
        if self.dwell_s is not None and not 0.0 <= self.dwell_s <= DWELL_S_MAX:
            raise CampaignError(f"--dwell-s {self.dwell_s} must lie in [0, {DWELL_S_MAX}] s")
        if self.dwell_s is not None and not self.dwell_s < dwell_window_s:
            raise CampaignError(f"--dwell-s {self.dwell_s} must lie in [0, {dwell_window_s}) s{dwell_window_text}")
        if self.p_min is not None and not 0.0 <= self.p_min < 1.0 / len(SINGLE_HYPOTHESES):
            raise CampaignError(f"--p-min {self.p_min} must lie in [0, 1/{len(SINGLE_HYPOTHESES)})")

    def scenario_dict(self, bank, failures: tuple[tuple[str, float] | FailureSpec, ...], seed: int,
                      mach: float | None = None, alt_ft: float | None = None) -> dict:
        """A run's scenario as the truth model's own plain data (``Scenario.to_dict``), so the
        record holds every truth setting (dither amplitudes, ARI, noise) and the run key
        changes when a truth default does. ``failures``: (name, time_s) pairs in this config's
        mode, or FailureSpecs (their own mode and value); ``mach`` / ``alt_ft`` None: the bank's design point. ValueError on a bad value."""
        scenario = Scenario(
            mach=float(mach if mach is not None else bank.mach),
            alt_ft=float(alt_ft if alt_ft is not None else bank.alt_ft),
            turbulence=self.turbulence, dither=self.dither_spec(),
            failures=tuple(f if isinstance(f, FailureSpec) else make_failure(f[0], f[1], self.mode)
                           for f in failures),
            duration_s=self.duration_s, seed=seed, feedback=self.feedback,
        )
        return scenario.to_dict()
