"""What every campaign kind is configured by: the flight settings they share, once.

A kind's config (``SingleCampaign``, ``DualCampaign``, ``EnvelopeCampaign``) is a frozen
dataclass derived from :class:`CampaignConfig`; it adds what is its own (cases, pairs,
points, failure times) and may change a shared field's default (runs, duration).
:meth:`CampaignConfig.check_common` checks the shared fields; each kind's ``validate``
calls it and checks its own.  Every check raises :class:`CampaignError` naming the bad
value and the valid range.

Turbulence: ``turbulence`` is one level or a comma list of distinct levels
(``none,light,moderate,severe``, :meth:`CampaignConfig.levels`); every kind flies each level
listed (``variants.fly_variants``, or the soak's own plan).

Failure mode: ``mode`` is one mode, ``NAME[=VALUE]`` (``complete``, ``stuck``, ``loss=0.5``,
``hardover=-1``; :func:`split_mode`), the failure every planned failure gets
(:meth:`CampaignConfig.failure`).  A kind that flies a list of modes (``MODE_LIST``, the single
campaign) takes a comma list of distinct modes (:meth:`CampaignConfig.modes`), each flown as a
variant; the others one mode.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from ...errors import F16mmaeError
from ...loop.estimator_options import COMMAND_LINE
from ...loop.estimator_options import check as check_estimator
from ...names import FEEDBACK_MODES, FLIGHT_S, TURBULENCE_LEVELS
from ...truth import DitherSpec, Scenario
from ...truth.actuators import ACTUATOR_MODES
from ...truth.failures import FailureSpec, make_failure
from ...truth.sensors import SENSOR_MODES


#: The most seeded runs per case (or pair, or point and case) a campaign plans.
RUNS_MAX = 1000
#: The largest multiple of the truth model's default dither amplitudes a campaign flies.
DITHER_SCALE_MAX = 5.0


class CampaignError(F16mmaeError):
    """A campaign argument is invalid, or a run failed; the message names it."""


def split_mode(text: str) -> tuple[str, float | None]:
    """``NAME[=VALUE]`` as (name lower-cased, value or None); ValueError when VALUE is no number."""
    name, _, value = text.strip().partition("=")
    if not value.strip():
        return name.strip().lower(), None
    try:
        return name.strip().lower(), float(value)
    except ValueError:
        raise ValueError(f"failure mode {text!r}: {value!r} is not a number (NAME=VALUE, e.g. loss=0.5)") from None


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
    #: The estimator settings this campaign overrides (``loop.estimator_options``: key -> value;
    #: unset ones stay the bank's recommended, on-line options off).
    estimator: Mapping[str, object] = field(default_factory=dict)

    #: Whether this kind flies a comma list of failure modes (module docstring).
    MODE_LIST = False

    def modes(self) -> tuple[str, ...]:
        """The failure modes listed in ``mode``, in the order given."""
        return tuple(x.strip() for x in self.mode.split(","))

    def failure(self, name: str, time_s: float):
        """The failure of component ``name`` at ``time_s`` in this config's (one) mode
        (``truth.failures.make_failure``; ValueError when the mode does not fit the component)."""
        mode, value = split_mode(self.mode)
        return make_failure(name, time_s, mode, value)

    def levels(self) -> tuple[str, ...]:
        """The turbulence levels listed in ``turbulence``, in the order given."""
        return tuple(x.strip() for x in self.turbulence.split(","))

    def estimator_options(self) -> dict:
        """The estimator settings this config overrides, in the table's order."""
        return {o.key: self.estimator[o.key] for o in COMMAND_LINE if o.key in self.estimator}

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
        levels = self.levels()
        bad = [x for x in levels if x not in TURBULENCE_LEVELS]
        if bad:
            raise CampaignError(f"unknown turbulence {', '.join(map(repr, bad))}; valid: {', '.join(TURBULENCE_LEVELS)}")
        if len(set(levels)) != len(levels):
            raise CampaignError(f"a turbulence level is listed twice in {self.turbulence!r}")
        modes = self.modes()
        if len(set(modes)) != len(modes):
            raise CampaignError(f"a failure mode is listed twice in {self.mode!r}")
        if len(modes) > 1 and not self.MODE_LIST:
            raise CampaignError(f"this campaign flies one failure mode, got {self.mode!r} "
                                f"(campaign single flies a list)")
        for m in modes:
            try:
                name, _ = split_mode(m)
            except ValueError as exc:
                raise CampaignError(str(exc)) from None
            if name not in ACTUATOR_MODES + SENSOR_MODES:
                raise CampaignError(f"unknown failure mode {m!r}; valid: actuators {', '.join(ACTUATOR_MODES)}; "
                                    f"sensors {', '.join(SENSOR_MODES)} (a value as NAME=VALUE, e.g. loss=0.5)")
        if self.feedback not in FEEDBACK_MODES:
            raise CampaignError(f"unknown feedback {self.feedback!r}; valid: {', '.join(FEEDBACK_MODES)}")
        if not 0.0 <= self.dither_scale <= DITHER_SCALE_MAX:
            raise CampaignError(f"--dither-scale {self.dither_scale} must lie in [0, {DITHER_SCALE_MAX}]")
        try:
            check_estimator(dict(self.estimator))
        except ValueError as exc:
            raise CampaignError(str(exc)) from None
        dwell = self.estimator.get("dwell_s")
        if dwell is not None and not dwell < dwell_window_s:
            raise CampaignError(f"--dwell-s {dwell} must lie in [0, {dwell_window_s}) s{dwell_window_text}")

    def scenario_dict(self, bank, failures: tuple[tuple[str, float] | FailureSpec, ...], seed: int,
                      mach: float | None = None, alt_ft: float | None = None,
                      turbulence: str | None = None, duration_s: float | None = None) -> dict:
        """A run's scenario as the truth model's own plain data (``Scenario.to_dict``), so the
        record holds every truth setting (dither amplitudes, ARI, noise) and the run key
        changes when a truth default does. ``failures``: (name, time_s) pairs in this config's
        mode, or FailureSpecs (their own mode and value); ``mach`` / ``alt_ft`` None: the
        bank's design point; ``turbulence`` None: this config's (single) level; ``duration_s``
        None: this config's. ValueError on a bad value."""
        scenario = Scenario(
            mach=float(mach if mach is not None else bank.mach),
            alt_ft=float(alt_ft if alt_ft is not None else bank.alt_ft),
            turbulence=self.turbulence if turbulence is None else turbulence, dither=self.dither_spec(),
            failures=tuple(f if isinstance(f, FailureSpec) else self.failure(*f) for f in failures),
            duration_s=self.duration_s if duration_s is None else duration_s, seed=seed, feedback=self.feedback,
        )
        return scenario.to_dict()
