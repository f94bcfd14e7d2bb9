"""The estimator as the closed loop sees it: the MMAE built from a model bank, fed ``z``, ``u``
and measured air data only.

:class:`Estimator` wraps the C++ ``core.HierarchicalBank`` (through the binding).  Its only
inputs are the absolute vectors ``z`` (7,) and ``u`` (5,) and the measured air data (Mach,
pressure altitude ft: the truth model's air-data sensor, ``truth.air_data``), copied into fresh
floats at the boundary; its settings come from the bank (``banks.bank_estimator_settings``) and
the caller's overrides.  Nothing else of the truth model reaches it.
"""
from __future__ import annotations

import math

import numpy as np

from .. import core
from ..banks import bank_estimator_settings, turbulence_bank_set
from ..names import (ADAPT_SET_TEMPERING_FULL, ADAPT_SET_TEMPERING_ROUGH, SENSORS, SET_TEMPERING_FULL,
                     SET_TEMPERING_MARGIN_STABILATORS, SINGLE_HYPOTHESES)
from ..truth.actuators import POSITION_LIMIT_RAD, RATE_LIMIT_RAD_S
from .estimator_options import CLOSED_LOOP, FILE_LOADERS, TABLE_PARSERS, bank_defaults, with_closed_loop_defaults


def core_arguments(settings: dict, nu: int = len(RATE_LIMIT_RAD_S)) -> dict:
    """The keyword arguments of ``core.HierarchicalBank`` for the estimator ``settings`` of a
    bank with ``nu`` inputs: ``actuator_limits`` (True) becomes the F-16 actuators' rate and
    position limits (``truth.actuators``: the actuator specification the estimator's designer
    has, as the lag in the bank; cpp/f16mmae/actuator_limits.h), never a measurement; an input
    beyond the five surfaces (the throttle of a bank that models it) has no actuator: +inf.
    ``adapt_counted_channel`` (a sensor's name) becomes ``adapt_counted_channels``, its bit, and
    ``adapt_excluded_channel`` ``adapt_excluded_channels``, ``adapt_level_scale_channel``
    ``adapt_level_scale_channels`` (``none``: no bit); ``calm_complete`` (its table) ``calm_complete_rho``;
    ``adapt_all_channels`` is the core's own-channels rule off (``estimator_options.scheduled_defaults``),
    ``maneuver_setting`` the options it has set there;
    ``trim_steady_air_data`` "off" makes the steady trim tracking's climb and Mach limits infinite
    (the air data's rates never freeze it; cpp/f16mmae/trim_tracker.h);
    ``set_tempering`` W becomes ``adapt_hypothesis_weight`` W and ``adapt_full_tempering``, the bits of
    ``names.SET_TEMPERING_FULL`` (with ``turbulence_banks``; else ``names.ADAPT_SET_TEMPERING_FULL``) in
    the level-0 order (``names.SINGLE_HYPOTHESES``),
    ``set_tempering_rough`` RHO (> 0) ``adapt_rough_rho`` RHO and ``adapt_rough_tempering``, the bits of
    ``names.ADAPT_SET_TEMPERING_ROUGH``, with ``set_tempering_rough_weight`` ``adapt_rough_weight``,
    ``set_tempering_rho`` ``adapt_spare_rho``, ``set_tempering_margin`` ``adapt_spare_margin`` and
    ``set_tempering_margin_stabilators`` ``adapt_spare_margin_over``, the bits of
    ``names.SET_TEMPERING_MARGIN_STABILATORS``."""
    out = dict(settings)
    out.pop("adapt_all_channels", None)
    out.pop("maneuver_setting", None)   # resolved by scheduled_defaults into the options it sets
    for key, load in FILE_LOADERS.items():   # a file option's table: {"F>C": k} (level1_allowance.h), {name: N}
        if key in out and not isinstance(out[key], dict):   # a dict: the table itself (a bank's N_k)
            out[key] = load(out[key])
    for key, parse in TABLE_PARSERS.items():   # a table option's text: {name: S}
        if key in out and not isinstance(out[key], dict):
            out[key] = parse(out[key])
    if "calm_complete" in out:   # the calm-air bounds by measurement (cpp/f16mmae/calm_air_complete.h)
        out["calm_complete_rho"] = out.pop("calm_complete")
    for name in ("counted", "excluded", "level_scale"):   # the sensor's channel as the core's bit mask over z (names.SENSORS' order)
        sensor = out.pop(f"adapt_{name}_channel", None)
        if sensor is not None and sensor != "none":   # none: no channel (the scheduled default turned off)
            out[f"adapt_{name}_channels"] = 1 << SENSORS.index(sensor.upper())
    if out.pop("trim_steady_air_data", "on") == "off":   # the air-data gate of steady tracking open
        out["trim_steady_climb_ft_s"] = out["trim_steady_mach_per_s"] = math.inf
    weight = out.pop("set_tempering", None)
    if weight is not None:   # the per-hypothesis tempering: the weight, and the fully tempered ones' bits
        out["adapt_hypothesis_weight"] = float(weight)
        full = SET_TEMPERING_FULL if out.get("turbulence_banks") else ADAPT_SET_TEMPERING_FULL
        out["adapt_full_tempering"] = sum(1 << SINGLE_HYPOTHESES.index(h) for h in full)
    rough = out.pop("set_tempering_rough", None)
    rough_weight = out.pop("set_tempering_rough_weight", None)
    if rough:   # the rough-air hypotheses' own share of s - 1 (0: none)
        out["adapt_rough_rho"] = float(rough)
        if rough_weight is not None:
            out["adapt_rough_weight"] = float(rough_weight)
        out["adapt_rough_tempering"] = sum(1 << SINGLE_HYPOTHESES.index(h) for h in ADAPT_SET_TEMPERING_ROUGH)
    rho = out.pop("set_tempering_rho", None)
    if rho is not None:
        out["adapt_spare_rho"] = float(rho)
    if out.pop("set_tempering_margin", False):
        out["adapt_spare_margin"] = True
    if out.pop("set_tempering_margin_stabilators", False):
        out["adapt_spare_margin_over"] = sum(1 << SINGLE_HYPOTHESES.index(h) for h in SET_TEMPERING_MARGIN_STABILATORS)
    if out.pop("actuator_limits", False):
        free = [math.inf] * (nu - len(RATE_LIMIT_RAD_S))
        out["actuator_rate_limits_rad_s"] = [*RATE_LIMIT_RAD_S, *free]
        out["actuator_position_limits_rad"] = [*POSITION_LIMIT_RAD, *free]
    return out


def turbulence_set_of(model_bank):
    """The turbulence bank set (design/turbulence_banks.py) that ``--turbulence-banks`` flies
    with ``model_bank``: ValueError unless ``model_bank`` is one of its members (the loop flies
    that bank's inputs and trims: ``--tuning turbulence``)."""
    bank_set = turbulence_bank_set()
    hashes = [str(b.content_hash) for b in bank_set.banks]
    if str(model_bank.content_hash) not in hashes:
        start = bank_set.levels[bank_set.selector["start"]]
        raise ValueError(f"--turbulence-banks flies the turbulence bank set ({', '.join(bank_set.levels)}); "
                         f"give its bank as the model bank (--tuning turbulence, its {start} member), "
                         f"not {model_bank.tuning or model_bank.content_hash}")
    return bank_set


def flown_bank_hash(model_bank, settings: dict) -> str:
    """The hash that names what the estimator flies: the turbulence bank set's (its file's
    content hash, as mmae-daemon's status carries it) with ``turbulence_banks``, else the bank's."""
    if settings.get("turbulence_banks"):
        return str(turbulence_set_of(model_bank).set_hash)
    return str(model_bank.content_hash)


def _bank_set(model_bank, settings: dict):
    """``core.TurbulenceBankSet`` over the turbulence bank set's file (:func:`turbulence_set_of`)
    with ``settings`` (``model_bank``'s recommended ones and the options given): its members made
    by the executive's rule (cpp/executive/turbulence_set_bank.h: the adaptation on, each
    filter's power per channel it reads, the file's reference, trim tracking and load-factor
    tempering unless given), what mmae-daemon --turbulence-banks runs."""
    bank_set = turbulence_set_of(model_bank)
    own = core_arguments({k: v for k, v in settings.items() if k not in CLOSED_LOOP}, model_bank.nu)
    own.pop("turbulence_banks", None)   # read by core_arguments (the set's fully tempered hypotheses)
    return core.TurbulenceBankSet(bank_set.source, **own)


class Estimator:
    """The MMAE (the C++ ``core.HierarchicalBank`` through the binding) as the loop sees it.

    ``Estimator(model_bank, **options)``: the settings of ``core.HierarchicalBank``
    (``p_min``, ``threshold``, ``dwell_s``) are the bank's recommended ones
    (:func:`bank_estimator_settings`, the bank's typed fields) updated by ``options`` (which win);
    ``settings`` holds the result (with the closed loop's defaults written out:
    ``estimator_options.with_closed_loop_defaults``).  A scheduled bank's floor is its nodes' own (``node_p_min``,
    core.HierarchicalBank) unless ``options`` gives ``p_min``; ``settings`` then names no ``p_min``, so that
    ``Estimator(model_bank, **settings)`` is the same estimator.  Per frame: ``schedule(mach, pressure_altitude_ft)`` (the
    air data measured with z), ``update(z) -> z_hat``, then ``propagate(u)``; z and u absolute
    (the core subtracts the bank's z_trim / u_trim and returns z_hat absolute).  Nothing else
    flows in."""

    def __init__(self, model_bank, **options) -> None:
        #: The estimator settings in force: the bank's recommended ones, then ``options``, then a
        #: scheduled bank's defaults (``estimator_options.bank_defaults``: own channels, the
        #: running start its file recommends) and the closed loop's (``with_closed_loop_defaults``:
        #: the adaptive dither with a bank set).
        self.settings: dict = with_closed_loop_defaults(bank_defaults(bank_estimator_settings(model_bank, options),
                                                                      model_bank))
        if self.settings.get("turbulence_banks"):
            self._bank = _bank_set(model_bank, self.settings)
        else:
            # a scheduled bank's per-node floors unless a p_min was given (then that everywhere)
            own = {k: v for k, v in self.settings.items() if k not in CLOSED_LOOP}  # the loop's (flight.py)
            self._bank = core.HierarchicalBank(model_bank, **core_arguments(own, model_bank.nu),
                                               node_p_min="p_min" not in options)
            if "p_min" not in options and model_bank.schedule is not None:
                # the floor in force is each node's, not the bank's one p_min (that floor only before
                # the first air data): the settings name no p_min, so Estimator(bank, **settings),
                # a record flown again, has the nodes' floors too
                self.settings.pop("p_min", None)
        self.bank_hash = flown_bank_hash(model_bank, self.settings)
        #: The hypothesis declared by the last update (a back-out declares NONE), or None.
        self.last_declaration: str | None = None

    @classmethod
    def fresh(cls, model_bank, **options) -> "Estimator":
        """An estimator in its start state (level 0, NONE presumed, states zero).

        Building the 79 stored filters is a sizeable share of a short flight's cost, so one
        estimator per (bank hash, options) is kept per process and ``reset()`` for the next
        flight -- same result as a new one (tests/python/test_closedloop.py)."""
        key = (str(model_bank.content_hash), tuple(sorted(options.items())))
        est = _ESTIMATORS.pop(key, None)
        if est is None:
            est = cls(model_bank, **options)
        else:
            est.reset()
        _ESTIMATORS[key] = est
        while len(_ESTIMATORS) > 4:
            _ESTIMATORS.pop(next(iter(_ESTIMATORS)))
        return est

    def reset(self) -> None:
        self._bank.reset()
        self.last_declaration = None

    def schedule(self, mach, pressure_altitude_ft) -> None:
        """The measured air data for this frame (before its ``update``); a non-finite value
        leaves the last usable one in force and is counted (``air_data_rejected``)."""
        self._bank.schedule(float(mach), float(pressure_altitude_ft))  # fresh floats: no object crosses

    def update(self, z) -> np.ndarray:
        z = np.array(z, dtype=float).reshape(-1)  # a fresh float copy: no object crosses over
        self.last_declaration = self._bank.update(z)
        return self._bank.z_hat

    def propagate(self, u) -> None:
        self._bank.propagate(np.array(u, dtype=float).reshape(-1))

    @property
    def core_bank(self):
        """The ``core.HierarchicalBank`` itself (for a flight flown whole in C++, loop/flight.py)."""
        return self._bank

    @property
    def fixed_size(self) -> bool:
        """True when the bank runs the fixed-size F-16 instantiation."""
        return bool(self._bank.fixed_size)

    @property
    def hypotheses(self) -> tuple[str, ...]:
        """Names of the hypotheses on line, in the order of ``probabilities``."""
        return tuple(self._bank.hypotheses)

    @property
    def probabilities(self) -> np.ndarray:
        return self._bank.probabilities

    @property
    def declared(self) -> str:
        """The hypothesis currently declared (NONE when no failure is declared)."""
        return str(self._bank.declared)

    @property
    def turbulence_scale(self) -> float:
        """The core's turbulence-adaptation scale s in force (1.0 with the adaptation off)."""
        return float(self._bank.turbulence_scale)

    @property
    def dwell_frames_in_force(self) -> int:
        """The declarer's dwell in frames in force for its candidate on the last update (0: no
        hypothesis above the threshold; cpp/f16mmae/declarer.h): what its evidence dwell scales N_k by."""
        return int(self._bank.dwell_frames_in_force)

    @property
    def turbulence_power_ratio(self) -> float:
        """The adaptation's averaged residual power ratio rho (of the running member for a set)."""
        return float(self._bank.turbulence_power_ratio)

    @property
    def measured_power_ratio(self) -> float:
        """The measured residual power ratio the air is read by (the adaptive dither's input,
        loop/flight.py): the set member's in force (the selector's measure), else the turbulence
        adaptation's measured rho-bar; NaN for one bank without the adaptation. The status over
        LCM carries the same number (``turbulence_power_ratio``)."""
        if self.settings.get("turbulence_banks"):
            return float(self._bank.turbulence_power_ratio)
        return float(self._bank.measured_power_ratio) if self.settings.get("adapt_turbulence") else math.nan

    @property
    def turbulence_member(self) -> int | None:
        """The index of the turbulence set's member in force (None: not a set)."""
        return int(self._bank.active) if self.settings.get("turbulence_banks") else None

    @property
    def level(self) -> int:
        return int(self._bank.level)

    @property
    def air_data(self) -> tuple[float, float]:
        """(Mach, pressure altitude ft) in force: the last usable ``schedule`` value."""
        return tuple(self._bank.air_data)

    @property
    def air_data_rejected(self) -> int:
        """``schedule`` calls with a non-finite value since the last reset."""
        return int(self._bank.air_data_rejected)


_ESTIMATORS: dict[tuple, Estimator] = {}
