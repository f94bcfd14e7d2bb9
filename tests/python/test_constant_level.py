"""The ``constant`` failure model (a failed sensor reading an unknown constant near its trim,
design/hypotheses.py): the core's likelihood against the exact predictive density of an
unknown constant observed in Gaussian noise (a flat prior: after n readings the next one is
N(mean_n, A (1 + 1/n)), written out with SciPy), the tracked level's variance through a
restart, and the design's widths and level noises for ``constant=VEL`` and ``constant=VEL+ROL``."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from f16mmae import core, names
from f16mmae.design import bank, hypotheses
from f16mmae.design.tuning import load_tuning, tuning_from_dict
from f16mmae.truth import sensors

from test_failure_models import footing, small_models


def _stripped_gauss(m, r, keep):
    """ln N(r_G; 0, A_GG) with the whole A's (2 pi)^{m/2} |A|^{1/2} put back (the stripped form;
    the failed channel's density then enters as it is)."""
    a = np.asarray(m.a)
    return (stats.multivariate_normal(np.zeros(len(keep)), a[np.ix_(keep, keep)]).logpdf(r[keep])
            + 0.5 * len(r) * np.log(2 * np.pi) + 0.5 * np.linalg.slogdet(a)[1])


def test_a_constant_level_has_the_exact_predictive_density_of_an_unknown_constant():
    width = 9.9
    a_probe = small_models(np.array([0.0, width, 0.0]))[1]
    a11 = float(np.asarray(a_probe.a)[1, 1])
    models = small_models(np.array([0.0, width, 0.0]), np.array([0.0, 1e-12 * a11, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6)
    rng = np.random.default_rng(11)
    readings = 2.4 + np.sqrt(a11) * rng.standard_normal(200)
    eps = 1e-3
    for n, v in enumerate(readings):
        z = np.array([0.1 * rng.standard_normal(), v, 0.05 * rng.standard_normal()])
        fb.step(z, np.zeros(2))
        r = np.asarray(fb.residuals)[1]
        assert r[1] == v
        if n == 0:
            u = np.log(1.0 / width)
        else:
            prev = readings[:n]
            pred = stats.norm(prev.mean(), np.sqrt(a11 * (1.0 + 1.0 / n)))
            u = np.log((1 - eps) * pred.pdf(v) + eps / width)
        expect = _stripped_gauss(models[1], r, [0, 2]) + u + footing(models[1], np.asarray(models[0].a))
        assert fb.log_likelihoods[1] == pytest.approx(expect, rel=1e-7, abs=1e-7), n


def test_a_restarted_level_starts_again_from_one_reading():
    """After a jump the level is the new reading with the variance of one reading: the next
    reading's predictive variance is 2 A (plus q), not the long-run A (1 + 1/n)."""
    width = 9.9
    a11 = float(np.asarray(small_models(np.array([0.0, width, 0.0]))[1].a)[1, 1])
    q = 1e-12 * a11
    models = small_models(np.array([0.0, width, 0.0]), np.array([0.0, q, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6)
    seq = [1.0] * 30 + [1.0 + 40 * np.sqrt(a11), 1.0 + 40 * np.sqrt(a11) + 0.3]
    for v in seq:
        fb.step(np.array([0.0, v, 0.0]), np.zeros(2))
    r = np.asarray(fb.residuals)[1]
    u = np.log((1 - 1e-3) * stats.norm(seq[-2], np.sqrt(2 * a11 + q)).pdf(seq[-1]) + 1e-3 / width)
    assert fb.log_likelihoods[1] == pytest.approx(_stripped_gauss(models[1], r, [0, 2]) + u
                                                  + footing(models[1], np.asarray(models[0].a)), abs=1e-9)


def test_constant_vel_design_widths_and_level_noise():
    base = load_tuning("tuned").to_dict()
    tun = tuning_from_dict({**base, "failure_model": {"default": "complete", "constant": ["VEL"]}},
                           default_name="constant-vel")
    assert tun.failure_model == "constant=VEL"
    d = bank.design_bank(0.4, 20_000.0, tun, hypotheses=("NONE", "VEL", "AOA", "VEL+PIT"))
    for name in ("VEL", "VEL+PIT"):
        m = d.filter(name).model
        assert list(m.uninformative_width) == [6 * 1.65] + [0.0] * (names.NZ - 1)
        assert m.uninformative_level_q[0] == pytest.approx(1e-6 * sensors.NOISE_SIGMA[0] ** 2, rel=1e-15)
        assert np.count_nonzero(m.uninformative_level_q) == 1
    assert not np.any(d.filter("AOA").model.uninformative_width)
    # the filter matrices are the complete model's: only the density of the failed channel differs
    ref = bank.design_bank(0.4, 20_000.0, load_tuning("tuned"), hypotheses=("NONE", "VEL"))
    np.testing.assert_array_equal(d.filter("VEL").gains.k, ref.filter("VEL").gains.k)


def test_constant_rol_takes_the_gyro_noise_sigma_as_its_level_uncertainty():
    """constant=VEL+ROL: a failed roll gyro reads a level uniform over 6 noise sigmas (0.6 deg/s)
    with a level random walk of 1e-6 of its noise variance, in every hypothesis that fails ROL;
    the filters are the complete model's and the hypotheses without ROL those of constant=VEL."""
    base = load_tuning("tuned").to_dict()
    tun = tuning_from_dict({**base, "failure_model": {"default": "complete", "constant": ["VEL", "ROL"]}},
                           default_name="constant-vel-rol")
    assert tun.failure_model == "constant=VEL+ROL"
    hyps = ("NONE", "VEL", "ROL", "ROL+PIT", "LF")
    d = bank.design_bank(0.4, 20_000.0, tun, hypotheses=hyps)
    vel = bank.design_bank(0.4, 20_000.0, tuning_from_dict({**base, "failure_model": "constant=VEL"},
                                                           default_name="constant-vel"), hypotheses=hyps)
    j = names.SENSORS.index("ROL")
    for name in ("ROL", "ROL+PIT"):
        m = d.filter(name).model
        assert m.uninformative_width[j] == pytest.approx(6 * np.radians(0.1), rel=1e-12)
        assert m.uninformative_level_q[j] == pytest.approx(1e-6 * np.radians(0.1) ** 2, rel=1e-12)
        assert np.count_nonzero(m.uninformative_width) == np.count_nonzero(m.uninformative_level_q) == 1
        np.testing.assert_array_equal(d.filter(name).gains.k, vel.filter(name).gains.k)
        assert not np.any(vel.filter(name).model.uninformative_width)
    for name in ("NONE", "VEL", "LF"):
        np.testing.assert_array_equal(d.filter(name).model.uninformative_width, vel.filter(name).model.uninformative_width)
        np.testing.assert_array_equal(d.filter(name).gains.k, vel.filter(name).gains.k)


@pytest.mark.parametrize("bad, message", [
    ("constant=PIT", "component PIT has no trim uncertainty; constant applies to VEL, AOA, ROL"),
    ("constant", "constant cannot be the default"),
])
def test_constant_is_refused_where_no_trim_uncertainty_is_known(bad, message):
    with pytest.raises(ValueError, match=message):
        hypotheses.component_models(bad)
