"""The per-hypothesis tempering (``--set-tempering W``; cpp/f16mmae/turbulence_adaptation.h): the
option reaches the core as the weight and the fully tempered hypotheses' bits, bad values are
refused by name, and on each frame at most one hypothesis' likelihood differs from the shipped
tempering's: the best-fitting failure hypothesis, never NONE or a fully tempered one."""
from __future__ import annotations

import numpy as np
import pytest

import f16mmae.design.turbulence_banks  # noqa: F401  (registers the turbulence bank set with banks.py)
from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.loop.estimator import core_arguments
from f16mmae.loop.estimator_options import check
from f16mmae.names import SET_TEMPERING_FULL, SINGLE_HYPOTHESES


def test_the_option_becomes_the_weight_and_the_fully_tempered_hypotheses_bits():
    args = core_arguments({"set_tempering": 0.25})
    assert args["adapt_hypothesis_weight"] == 0.25
    bits = args["adapt_full_tempering"]
    assert [h for i, h in enumerate(SINGLE_HYPOTHESES) if bits >> i & 1] == list(SET_TEMPERING_FULL)
    assert bits & 0b110 == 0b110   # the stabilators (LS, RS: level-0 slots 1 and 2) among them
    assert "set_tempering" not in args
    assert "adapt_hypothesis_weight" not in core_arguments({})


def test_bad_values_are_refused_by_name():
    with pytest.raises(ValueError, match="--set-tempering"):
        check({"set_tempering": 0.0, "turbulence_banks": True})
    with pytest.raises(ValueError, match="--set-tempering"):
        check({"set_tempering": 1.5, "turbulence_banks": True})
    with pytest.raises(ValueError, match="turbulence-banks"):
        check({"set_tempering": 0.5})
    check({"set_tempering": 0.5, "turbulence_banks": True})
    bank = load_bank("turbulence")[2]
    with pytest.raises(ValueError, match="adapt_hypothesis_weight"):
        core.HierarchicalBank(bank, adapt_turbulence=True, adapt_hypothesis_weight=0.0)
    with pytest.raises(ValueError, match="adapt_hypothesis_weight below 1 needs the common scale"):
        core.HierarchicalBank(bank, adapt_turbulence=True, adapt_hypothesis_weight=0.5, adapt_channel_weight=0.5)


def test_only_the_best_fitting_failure_hypothesis_is_spared():
    bank = load_bank("turbulence")[2]
    full = core_arguments({"set_tempering": 0.25})["adapt_full_tempering"]
    kw = dict(adapt_turbulence=True, adapt_reference=0.6, adapt_time_constant_s=1.0, p_min=1e-9)
    plain = core.HierarchicalBank(bank, **kw)
    spared = core.HierarchicalBank(bank, adapt_hypothesis_weight=0.25, adapt_full_tempering=full, **kw)
    rng = np.random.default_rng(7)
    z_trim, u_trim = np.asarray(bank.z_trim), np.asarray(bank.u_trim)
    sigma = np.sqrt(np.diag(np.asarray(bank.hypotheses[0].a)))
    differing, first = 0, None
    for i in range(192):   # 3 s of residuals 3 times the design's: s rises above 1
        z = z_trim + 3.0 * sigma * rng.standard_normal(len(z_trim))
        for b in (plain, spared):
            b.update(z)
            b.propagate(u_trim)
        if plain.level != 0 or spared.level != 0:
            break
        assert plain.turbulence_scale == spared.turbulence_scale   # the raw forms drive s
        diff = np.nonzero(np.asarray(plain.log_likelihoods) != np.asarray(spared.log_likelihoods))[0]
        assert len(diff) <= 1
        if len(diff):
            k = int(diff[0])
            assert k != 0 and not (full >> k & 1)
            assert plain.turbulence_scale > 1.0
            differing += 1
            first = i if first is None else first
    assert differing > 50
    assert first > 8   # not before the scale has caught up with the air (rho >= rho-bar / 2)
