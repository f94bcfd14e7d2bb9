"""Hypotheses that cover the failure (issue 13 item 1): the core's likelihood of a hypothesis
with uninformative channels against SciPy's multivariate normal times a uniform density (and
times a mixture of a normal at trim and a uniform), the
model checks that guard it, the bank file carrying the widths, and the ``cover`` design (a
failed surface as a random walk, a failed sensor uninformative over its full range)."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import stats
from scipy.linalg import expm

from f16mmae import core, names
from f16mmae.design import bank, hypotheses
from f16mmae.design.gains import steady_state_gains
from f16mmae.design.tuning import TuningError, load_tuning, tuning_from_dict
from f16mmae.truth import sensors


def small_models(width, level_q=None):
    """Three filters on a 3-state, 3-sensor system: NONE, sensor 1 failed (H row 1 removed)
    with the given widths, and sensor 2 failed in the paper's Gaussian form."""
    rng = np.random.default_rng(7)
    phi = np.diag([0.9, 0.8, 0.7]) + 0.05 * rng.standard_normal((3, 3))
    h = np.array([[1.0, 0.2, 0.0], [0.0, 1.0, 0.3], [0.4, 0.0, 1.0]])
    qd, r = np.diag([0.02, 0.03, 0.01]), np.diag([0.1, 0.2, 0.05])
    bd = np.eye(3)[:, :2]
    out = []
    for failed, w in ((None, None), (1, width), (2, None)):
        hk = h.copy()
        if failed is not None:
            hk[failed] = 0.0
        g = steady_state_gains(phi, hk, qd, r)
        out.append(core.FilterModel(phi=phi, bd=bd, h=hk, k=g.k, a=g.a, uninformative_width=w,
                                    uninformative_level_q=level_q if failed == 1 else None))
    return out


def level_predictive_variance(q, a_jj, n=1):
    """s of a random-walk level observed in noise a_jj for the reading n frames after the one
    that set it (variance a_jj then): the scalar Kalman recursion written out as the
    posterior variance of a Gaussian prior times n Gaussian readings, step by step."""
    p = a_jj
    for _ in range(n - 1):
        prior = p + q
        p = 1.0 / (1.0 / prior + 1.0 / a_jj)
    return p + q + a_jj


def footing(m, a0):
    """v_k of filter_bank.h (leading term stripped): (1/2) ln|A^0_FF|G| - sum_j (1/2) ln A_jj
    over the model's uninformative channels F, A^0 the no-failure filter's and A^0_FF|G its
    Schur complement A^0_FF - A^0_FG (A^0_GG)^-1 A^0_GF (F given the other channels G)."""
    a = np.asarray(m.a)
    f = [j for j in range(len(a)) if m.uninformative_width[j] > 0]
    g = [j for j in range(len(a)) if j not in f]
    schur = a0[np.ix_(f, f)] - a0[np.ix_(f, g)] @ np.linalg.solve(a0[np.ix_(g, g)], a0[np.ix_(g, f)])
    return 0.5 * np.linalg.slogdet(schur)[1] - sum(0.5 * np.log(a[j, j]) for j in f)


def expected_log_likelihood(m, r, frames, strip=False, a0=None):
    """SciPy's log-likelihood of filter model ``m`` for residual ``r`` on the last of ``frames``
    (readings as perturbations; the level of an uninformative channel is set by the first frame
    and nothing jumps before the last): a normal over the informative channels times, per
    uninformative channel, a uniform over W on the first frame, then the level's predictive
    normal mixed with a jump (1e-3) anywhere in W.  ``strip``: plus (2 pi)^{m/2} |A|^{1/2}, and
    the failed channels put on the footing of ``a0``, the no-failure filter's A."""
    a, z, n = np.asarray(m.a), frames[-1], len(frames) - 1
    nz = len(z)
    keep = [j for j in range(nz) if not m.uninformative_width[j] > 0]
    full = stats.multivariate_normal(np.zeros(len(keep)), a[np.ix_(keep, keep)]).logpdf(r[keep])
    for j in range(nz):
        if m.uninformative_width[j] > 0:
            assert r[j] == z[j]  # H row zero: the reading itself (perturbation)
            if n == 0 or m.uninformative_level_q[j] == 0:  # level unknown: uniform over W
                full += stats.uniform(loc=z[j] - 1.0, scale=m.uninformative_width[j]).logpdf(z[j])
            else:  # the level set by the first frame, then its predictive density or a jump
                s_j = level_predictive_variance(m.uninformative_level_q[j], a[j, j])
                eps = 1e-3
                full += np.log((1 - eps) * stats.norm(0.0, np.sqrt(s_j)).pdf(z[j] - frames[0][j])
                               + eps * stats.uniform(loc=z[j] - 1.0, scale=m.uninformative_width[j]).pdf(z[j]))
    # the stripped form drops (2 pi)^{-m/2} |A|^{-1/2} of the filter's whole A
    return full + (0.5 * nz * np.log(2 * np.pi) + 0.5 * np.linalg.slogdet(a)[1] + footing(m, a0) if strip else 0.0)


@pytest.mark.parametrize("level_q", [0.0, 0.05])
@pytest.mark.parametrize("strip", [False, True])
def test_likelihood_is_normal_times_uniform_then_the_level(strip, level_q):
    width = np.array([0.0, 7.5, 0.0])
    models = small_models(width, np.array([0.0, level_q, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6, strip_leading_term=strip)
    frames = [np.array([0.3, 2.9, -0.2]), np.array([0.1, 3.3, 0.25])]
    u = np.array([0.2, -0.1])
    for n, z in enumerate(frames):
        fb.update(z)
        got, res = fb.log_likelihoods, np.asarray(fb.residuals)
        for k, m in enumerate(models):
            expect = expected_log_likelihood(m, res[k], frames[:n + 1], strip, np.asarray(models[0].a))
            assert got[k] == pytest.approx(expect, rel=1e-9, abs=1e-9), (n, k)
        fb.propagate(u)


def test_a_level_that_jumps_restarts_at_the_reading():
    models = small_models(np.array([0.0, 7.5, 0.0]), np.array([0.0, 0.05, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6)
    zs = [np.array([0.3, 0.2, -0.2]), np.array([0.3, 3.5, -0.2]), np.array([0.3, 3.5, -0.2])]
    out = []
    for z in zs:
        fb.step(z, np.zeros(2))
        out.append(fb.log_likelihoods[1])
    a11 = float(np.asarray(models[1].a)[1, 1])
    s_j = level_predictive_variance(0.05, a11)   # a reading one frame after the level's (re)start
    g = (s_j - a11) / s_j
    # frame 2: a jump of 3.3 against s_j: the uniform branch (eps / W) is far the likelier ...
    stay = np.log(1 - 1e-3) + stats.norm(0, np.sqrt(s_j)).logpdf(3.3)
    jump = np.log(1e-3 / 7.5)
    assert jump > stay
    # ... so frame 3 sees the level at 3.5 (restarted), not at 0.2 + g * 3.3
    r3 = np.asarray(fb.residuals)[1]
    at_restart = np.log((1 - 1e-3) * stats.norm(0, np.sqrt(s_j)).pdf(r3[1] - 3.5) + 1e-3 / 7.5)
    s_t = level_predictive_variance(0.05, a11, 2)
    tracked = np.log((1 - 1e-3) * stats.norm(0, np.sqrt(s_t)).pdf(r3[1] - (0.2 + g * 3.3)) + 1e-3 / 7.5)
    a = np.asarray(models[1].a)
    keep = [0, 2]
    gauss = stats.multivariate_normal(np.zeros(2), a[np.ix_(keep, keep)]).logpdf(r3[keep]) + \
        1.5 * np.log(2 * np.pi) + 0.5 * np.linalg.slogdet(a)[1]
    assert out[2] == pytest.approx(gauss + at_restart + footing(models[1], np.asarray(models[0].a)), abs=1e-9)
    assert abs(at_restart - tracked) > 1.0


def test_a_new_filter_forgets_the_level():
    models = small_models(np.array([0.0, 7.5, 0.0]), np.array([0.0, 0.05, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6)
    fb.step(np.array([0.3, 2.9, -0.2]), np.zeros(2))
    fb.reset()
    fb.update(np.array([0.3, -4.0, -0.2]))  # first frame again: uniform, whatever the jump
    first = core.FilterBank(models, p_min=1e-6)
    first.update(np.array([0.3, -4.0, -0.2]))
    assert fb.log_likelihoods[1] == first.log_likelihoods[1]


@pytest.mark.parametrize("level_q", [0.0, 0.05])
def test_floor_of_a_tracked_level_hypothesis_carries_the_levels_occam_factor(level_q):
    """The floor of a hypothesis whose failed sensor tracks a level is p_min times the
    level's Occam factor (uniform density over W against the Gaussian's peak, SciPy); with
    no level memory (q = 0) it is p_min. Every frame: p_k = max(f_k, s b_k), b the Bayes
    posterior of the bank's own log-likelihoods."""
    p_min, width = 1e-3, 7.5
    models = small_models(np.array([0.0, width, 0.0]), np.array([0.0, level_q, 0.0]))
    fb = core.FilterBank(models, p_min=p_min)
    a11 = float(np.asarray(models[1].a)[1, 1])
    occam = stats.uniform(scale=width).logpdf(0.5) - stats.norm(0.0, np.sqrt(a11)).logpdf(0.0)
    floors = np.array([p_min, p_min * np.exp(occam) if level_q > 0 else p_min, p_min])
    np.testing.assert_allclose(fb.probabilities[1:], floors[1:], rtol=1e-12)
    rng = np.random.default_rng(3)
    p = fb.probabilities
    for _ in range(40):
        fb.update(rng.normal(0.0, 0.4, 3))
        b = p * np.exp(fb.log_likelihoods - fb.log_likelihoods.max())
        b /= b.sum()
        p = fb.probabilities
        top = int(np.argmax(b))
        np.testing.assert_allclose(p, np.maximum(floors, p[top] / b[top] * b), rtol=1e-9, atol=1e-15)
        assert p.sum() == pytest.approx(1.0, abs=1e-12)
        fb.propagate(np.zeros(2))


def test_uninformative_reading_leaves_the_likelihood_unchanged_whatever_it_reads():
    """With no trim weight the reading does not enter at all."""
    models = small_models(np.array([0.0, 7.5, 0.0]))
    out = []
    for reading in (0.0, 3.0, -3.5, 1e3):
        fb = core.FilterBank(models, p_min=1e-6)
        fb.update(np.array([0.3, reading, -0.2]))
        out.append(fb.log_likelihoods[1])
    assert out == pytest.approx([out[0]] * 4, abs=0.0)


def test_widths_are_checked():
    (none, failed, _) = small_models(np.array([0.0, 7.5, 0.0]))
    with pytest.raises(ValueError, match="channel 0 is uninformative .* h row is not zero"):
        core.FilterModel(phi=none.phi, bd=none.bd, h=none.h, k=none.k, a=none.a,
                         uninformative_width=np.array([1.0, 0.0, 0.0]))
    for bad, msg in (([0.0, -1.0, 0.0], r"uninformative_width\[1\] must be finite and >= 0"),
                     ([0.0, np.inf, 0.0], r"uninformative_width\[1\] must be finite")):
        with pytest.raises(ValueError, match=msg):
            core.FilterModel(phi=failed.phi, bd=failed.bd, h=failed.h, k=failed.k, a=failed.a,
                             uninformative_width=np.array(bad))
    for bad_w, msg in (([0.0, -1.0, 0.0], r"uninformative_level_q\[1\] must be finite and >= 0"),
                       ([0.5, 0.0, 0.0], r"uninformative_level_q\[0\] .* 0 unless the channel is uninformative")):
        with pytest.raises(ValueError, match=msg):
            core.FilterModel(phi=failed.phi, bd=failed.bd, h=failed.h, k=failed.k, a=failed.a,
                             uninformative_width=np.array([0.0, 7.5, 0.0]), uninformative_level_q=np.array(bad_w))
    a = np.array(failed.a)
    a[0, 1] = a[1, 0] = 1e-3
    with pytest.raises(ValueError, match="A couples it to channel 0"):
        core.FilterModel(phi=failed.phi, bd=failed.bd, h=failed.h, k=failed.k, a=a,
                         uninformative_width=np.array([0.0, 7.5, 0.0]))


@pytest.fixture(scope="module")
def cover_design():
    tuning = tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": "cover",
                               "failed_surface_q": 3e-4}, default_name="cover")
    return bank.design_bank(0.4, 20_000.0, tuning, hypotheses=names.SINGLE_HYPOTHESES + ("LS+PIT",))


def test_cover_sensor_hypothesis_is_uninformative_over_the_full_range(cover_design):
    """Every sensor but the pitch gyro over its full range; PIT over its derived width by default
    (design/level_width.py, DEFAULT_WIDTHS)."""
    full = [hi - lo for lo, hi in sensors.FULL_SCALE]
    for name in names.SENSORS:
        w = cover_design.filter(name).model.uninformative_width
        j = names.SENSORS.index(name)
        expected = cover_design.level_widths["PIT"]["width"] if name == "PIT" else full[j]
        assert w[j] == expected and np.count_nonzero(w) == 1
        t = cover_design.filter(name).model.uninformative_level_q
        ratio = {"AOA": 1e-3, "VEL": 1e-4}.get(name, 0.01)  # the default walk (design/tuning.py)
        assert t[j] == pytest.approx(ratio * sensors.NOISE_SIGMA[j] ** 2, rel=1e-15) and np.count_nonzero(t) == 1
    assert not np.any(cover_design.filter("LS").model.uninformative_width)
    assert np.count_nonzero(cover_design.filter("LS+PIT").model.uninformative_width) == 1


def test_cover_failed_surface_is_a_random_walk(cover_design):
    dt = 1.0 / cover_design.frame_rate_hz
    none = cover_design.filter("NONE").model
    n_air = names.NX - names.NU
    for name in ("LS", "RUD", "LS+PIT"):
        m = cover_design.filter(name).model
        i = n_air + names.ACTUATORS.index(names.failed_components(name)[0])
        # independent: the matrix exponential of F with the surface's row removed
        f = cover_design.continuous.f.copy()
        f[i, :] = 0.0
        assert np.allclose(m.phi, expm(f * dt), atol=1e-12)
        assert m.phi[i, i] == pytest.approx(1.0, abs=1e-15) and none.phi[i, i] < 0.75
        assert not np.any(m.bd[:, names.ACTUATORS.index(names.failed_components(name)[0])])
        # the walk's noise: q dt on its diagonal, beyond the no-failure model's (zero there)
        assert m.qd[i, i] - none.qd[i, i] == pytest.approx(3e-4 * dt, rel=1e-9)
    # sensors keep the no-failure dynamics
    assert np.array_equal(cover_design.filter("PIT").model.phi, none.phi)


def test_cover_bank_round_trips_its_widths(cover_design, tmp_path):
    loaded = bank.write_bank(cover_design, tmp_path / "cover.f16bank")
    for h, f in zip(loaded.hypotheses, cover_design.filters):
        assert np.array_equal(h.uninformative_width, f.model.uninformative_width)
        assert np.array_equal(h.uninformative_level_q, f.model.uninformative_level_q)
    assert '"failure_model":"cover"' in core.load_bank(str(tmp_path / "cover.f16bank")).metadata


def test_complete_design_has_no_uninformative_channel():
    assert not load_tuning("tuned").failure_model != "complete"
    d = bank.design_bank(0.4, 20_000.0, "tuned", hypotheses=("NONE", "PIT", "LS"))
    assert not any(np.any(f.model.uninformative_width) for f in d.filters)
    assert np.array_equal(d.filter("LS").model.phi, d.filter("NONE").model.phi)


def test_tuning_refuses_a_bad_failure_model():
    base = load_tuning("tuned").to_dict()
    with pytest.raises(TuningError, match="failure_model 'partial' is not a failure model; valid: complete, cover"):
        tuning_from_dict({**base, "failure_model": "partial"})
    with pytest.raises(TuningError, match="failed_surface_q = -1 must be a finite number > 0"):
        tuning_from_dict({**base, "failure_model": "cover", "failed_surface_q": -1})
    with pytest.raises(TuningError, match=r"failed_sensor_level_q = -1 must be a finite number >= 0"):
        tuning_from_dict({**base, "failure_model": "cover", "failed_sensor_level_q": -1})
    assert hypotheses.FAILURE_MODELS == ("complete", "cover", "constant")


def test_failed_sensor_level_q_per_sensor():
    base = {**load_tuning("tuned").to_dict(), "failure_model": "cover"}
    tun = tuning_from_dict({**base, "failed_sensor_level_q": {"PIT": 0.0, "AY": 0.05}}, default_name="per")
    # the sensors not named keep their default (VEL 1e-4, AOA 1e-3, the rest 0.01)
    assert list(tun.sensor_level_q()) == [1e-4, 1e-3, 0.0, 0.01, 0.01, 0.01, 0.05]
    assert list(tuning_from_dict({**base, "failed_sensor_level_q": 0.02}).sensor_level_q()) == [0.02] * 7
    with pytest.raises(TuningError, match="unknown sensor 'MACH' in failed_sensor_level_q; valid: VEL, AOA, PIT"):
        tuning_from_dict({**base, "failed_sensor_level_q": {"MACH": 1e-4}})
    with pytest.raises(TuningError, match=r"failed_sensor_level_q.AY = -0.1 must be a finite number >= 0"):
        tuning_from_dict({**base, "failed_sensor_level_q": {"AY": -0.1}})
    d = bank.design_bank(0.4, 20_000.0, tun, hypotheses=("NONE", "AOA", "PIT", "AY", "PIT+AY", "LS+AOA"))
    for name, comp, ratio in (("AOA", "AOA", 1e-3), ("PIT", "PIT", 0.0), ("AY", "AY", 0.05),
                              ("PIT+AY", "PIT", 0.0), ("PIT+AY", "AY", 0.05), ("LS+AOA", "AOA", 1e-3)):
        j = names.SENSORS.index(comp)
        # q_j per frame is the ratio times the sensor's noise variance (truth.sensors)
        assert d.filter(name).model.uninformative_level_q[j] == pytest.approx(
            ratio * sensors.NOISE_SIGMA[j] ** 2, rel=1e-15, abs=0.0), (name, comp)
    assert not np.any(d.filter("NONE").model.uninformative_level_q)


def test_failed_surface_q_per_surface():
    base = {**load_tuning("tuned").to_dict(), "failure_model": "cover"}
    tun = tuning_from_dict({**base, "failed_surface_q": {"LS": 1e-3, "RUD": 2e-4}}, default_name="per")
    # the surfaces not named keep their default
    assert tun.failed_surface_q == {"LS": 1e-3, "RS": 3e-4, "LF": 3e-5, "RF": 3e-5, "RUD": 2e-4}
    assert list(tun.surface_walk_q()) == [1e-3, 3e-4, 3e-5, 3e-5, 2e-4]
    assert list(tuning_from_dict({**base, "failed_surface_q": 5e-5}).surface_walk_q()) == [5e-5] * 5
    with pytest.raises(TuningError, match="unknown surface 'ELEV' in failed_surface_q; valid: LS, RS, LF, RF, RUD"):
        tuning_from_dict({**base, "failed_surface_q": {"ELEV": 1e-4}})
    with pytest.raises(TuningError, match=r"failed_surface_q.RF = 0 must be a finite number > 0"):
        tuning_from_dict({**base, "failed_surface_q": {"RF": 0}})
    d = bank.design_bank(0.4, 20_000.0, tun, hypotheses=("NONE", "LS", "LF", "RUD", "LS+RUD"))
    dt, n_air = 1.0 / d.frame_rate_hz, names.NX - names.NU
    none = d.filter("NONE").model
    for name, comp, q in (("LS", "LS", 1e-3), ("LF", "LF", 3e-5), ("RUD", "RUD", 2e-4),
                          ("LS+RUD", "LS", 1e-3), ("LS+RUD", "RUD", 2e-4)):
        i = n_air + names.ACTUATORS.index(comp)
        # a pure walk: the state's noise is q dt exactly (its row of F is zero)
        assert d.filter(name).model.qd[i, i] - none.qd[i, i] == pytest.approx(q * dt, rel=1e-9), (name, comp)


def test_failed_surface_q_dual_sets_the_walk_of_the_dual_hypotheses_only():
    """``failed_surface_q_dual``: the dual hypotheses' filters are those of a design whose every
    hypothesis has that walk; the singles' are the default design's, element for element."""
    base = {**load_tuning("tuned").to_dict(), "failure_model": "cover"}
    tun = tuning_from_dict({**base, "failed_surface_q_dual": {"LS": 1e-5, "RS": 1e-5}}, default_name="dual")
    assert tun.failed_surface_q_dual == {"LS": 1e-5, "RS": 1e-5, "LF": 3e-5, "RF": 3e-5, "RUD": 1e-3}
    assert list(tun.surface_walk_q()) == [3e-4, 3e-4, 3e-5, 3e-5, 1e-3]
    assert list(tun.surface_walk_q(dual=True)) == [1e-5, 1e-5, 3e-5, 3e-5, 1e-3]
    assert tun.to_dict()["failed_surface_q_dual"] == tun.failed_surface_q_dual
    # equal to the singles' walk, or absent: no dual walk of its own, and no metadata key
    same = tuning_from_dict({**base, "failed_surface_q_dual": 3e-4, "failed_surface_q": 3e-4}, default_name="same")
    assert same.failed_surface_q_dual == {} and "failed_surface_q_dual" not in same.to_dict()
    assert "failed_surface_q_dual" not in tuning_from_dict(base, default_name="none").to_dict()
    with pytest.raises(TuningError, match="unknown surface 'ELEV' in failed_surface_q_dual"):
        tuning_from_dict({**base, "failed_surface_q_dual": {"ELEV": 1e-4}})
    with pytest.raises(TuningError, match=r"failed_surface_q_dual.LS = -1 must be a finite number > 0"):
        tuning_from_dict({**base, "failed_surface_q_dual": {"LS": -1}})

    hyps = ("NONE", "LS", "PIT", "LS+PIT", "LS+RS", "LF+PIT")
    d = bank.design_bank(0.4, 20_000.0, tun, hypotheses=hyps)
    default = bank.design_bank(0.4, 20_000.0, tuning_from_dict(base, default_name="d"), hypotheses=hyps)
    every = bank.design_bank(0.4, 20_000.0, tuning_from_dict(
        {**base, "failed_surface_q": {"LS": 1e-5, "RS": 1e-5}}, default_name="e"), hypotheses=hyps)
    for name in hyps:
        want = every if name in names.DUAL_HYPOTHESES else default
        for field in ("phi", "bd", "qd"):
            np.testing.assert_array_equal(getattr(d.filter(name).model, field),
                                          getattr(want.filter(name).model, field), err_msg=f"{name} {field}")
        np.testing.assert_array_equal(d.filter(name).gains.k, want.filter(name).gains.k, err_msg=name)
    # the stabilator's walk in LS+PIT is 1e-5 dt; LF+PIT's flaperon keeps its 3e-5
    i = names.NX - names.NU
    none = d.filter("NONE").model
    assert d.filter("LS+PIT").model.qd[i, i] - none.qd[i, i] == pytest.approx(1e-5 / d.frame_rate_hz, rel=1e-9)
    assert d.filter("LS").model.qd[i, i] - none.qd[i, i] == pytest.approx(3e-4 / d.frame_rate_hz, rel=1e-9)


def level_posterior(q, a_jj, readings):
    """(mean, variance) of a random-walk level after ``readings`` (the first one sets it with
    variance a_jj): the product of the walked Gaussian prior and each reading's Gaussian,
    written out step by step."""
    mean, p = readings[0], a_jj
    for y in readings[1:]:
        prior = p + q
        p = 1.0 / (1.0 / prior + 1.0 / a_jj)
        mean = p * (mean / prior + y / a_jj)
    return mean, p


def level_log_density(m, r, level, p, q):
    """SciPy's log-likelihood of filter model ``m`` (leading term stripped, footing of the
    no-failure filter's A ``a0`` left out) for residual r when its one uninformative channel 1
    has the level (mean, variance p): the informative channels' normal times the level's
    predictive normal mixed with a jump (1e-3) anywhere in W."""
    a = np.asarray(m.a)
    keep = [0, 2]
    gauss = stats.multivariate_normal(np.zeros(2), a[np.ix_(keep, keep)]).logpdf(r[keep])
    s = p + q + a[1, 1]
    lvl = np.log((1 - 1e-3) * stats.norm(level, np.sqrt(s)).pdf(r[1]) + 1e-3 / m.uninformative_width[1])
    return gauss + lvl + 1.5 * np.log(2 * np.pi) + 0.5 * np.linalg.slogdet(a)[1]


@pytest.mark.parametrize("fresh", [True, False])
def test_a_hypothesis_on_its_floor_restarts_its_level_at_each_reading(fresh):
    """filter_bank.h's fresh floor levels: after a frame that leaves a failed-sensor hypothesis
    on its floor (p = p_min times its level's Occam factor), it predicts the next reading from
    a level restarted at that frame's reading (variance A_jj); otherwise (and always without
    them) from its level's Kalman update (or restart, when the jump is the likelier branch)."""
    q, width, eps = 0.05, 7.5, 1e-3
    models = small_models(np.array([0.0, width, 0.0]), np.array([0.0, q, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6, fresh_floor_levels=fresh)
    assert fb.fresh_floor_levels is fresh
    a0, a11 = np.asarray(models[0].a), float(np.asarray(models[1].a)[1, 1])
    v = footing(models[1], a0)
    occam = stats.uniform(scale=width).logpdf(0.5) - stats.norm(0.0, np.sqrt(a11)).logpdf(0.0)
    floor = 1e-6 * np.exp(occam)
    rng = np.random.default_rng(11)
    level = p = None
    restarts = 0
    for n in range(16):
        z = rng.normal(0.0, 0.3, 3)
        z[1] = 1.5 * np.sin(0.7 * n)   # a reading that wanders
        fb.update(z)
        r = np.asarray(fb.residuals)[1]
        if level is None:   # first frame: the level set at the reading
            level, p = r[1], a11
        else:
            expect = level_log_density(models[1], r, level, p, q) + v
            assert fb.log_likelihoods[1] == pytest.approx(expect, rel=1e-9, abs=1e-9), n
            s = p + q + a11
            if (1 - eps) * stats.norm(level, np.sqrt(s)).pdf(r[1]) >= eps / width:
                level, p = level + (p + q) / s * (r[1] - level), (p + q) * a11 / s
            else:
                level, p = r[1], a11
        if fresh and fb.probabilities[1] == pytest.approx(floor, rel=1e-12):
            level, p = r[1], a11
            restarts += 1
        fb.propagate(np.array([0.2, -0.1]))
    assert restarts >= (1 if fresh else 0)


def test_a_hypothesis_above_its_floor_keeps_tracking_its_level():
    """A hypothesis that holds probability keeps its tracked level with fresh floor levels on:
    its log-likelihood is that of the level tracked since its first reading."""
    q, width = 0.05, 7.5
    models = small_models(np.array([0.0, width, 0.0]), np.array([0.0, q, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6, initial_probabilities=np.array([0.25, 0.5, 0.25]),
                         fresh_floor_levels=True)
    a0, a11 = np.asarray(models[0].a), float(np.asarray(models[1].a)[1, 1])
    v = footing(models[1], a0)
    readings = []
    for n, y in enumerate([2.0, 2.1, 1.9, 2.05, 2.0]):
        fb.update(np.array([0.0, y, 0.0]))
        r = np.asarray(fb.residuals)[1]
        readings.append(r[1])
        assert fb.probabilities[1] > 0.1
        if n >= 1:
            level, p = level_posterior(q, a11, readings[:-1])
            expect = level_log_density(models[1], r, level, p, q) + v
            assert fb.log_likelihoods[1] == pytest.approx(expect, rel=1e-9, abs=1e-9), n
        fb.propagate(np.zeros(2))


def test_fresh_floor_levels_reach_the_estimator():
    """``fresh_floor_levels`` (``--fresh-floor-levels``) through the estimator's keyword table: the
    hierarchical bank's level 0 is the filter bank with the option, frame by frame, on cover
    hypotheses whose failed AOA wanders on its floor and then holds (a threshold no hypothesis
    reaches keeps the hierarchical bank at level 0); without it the levels keep following the
    reading there and the probabilities differ."""
    tuning = tuning_from_dict({**load_tuning("tuned").to_dict(), "failure_model": "cover"}, default_name="cover")
    design = bank.design_bank(0.4, 20_000.0, tuning)   # every dual: the hierarchical bank's level 1
    model_bank = bank.to_model_bank(design)
    fields = ("phi", "bd", "h", "k", "a", "uninformative_width", "uninformative_level_q")
    by_name = {m.name: m for m in model_bank.hypotheses}
    u0, z0 = np.asarray(model_bank.u_trim), np.asarray(model_bank.z_trim)
    j = names.SENSORS.index("AOA")
    rng = np.random.default_rng(5)
    frames = []
    for n in range(256):
        dz = rng.normal(0.0, 1.0, z0.size) * np.asarray(sensors.NOISE_SIGMA)
        dz[j] += 0.5 * sensors.NOISE_SIGMA[j] * (np.sin(0.2 * n) if n < 128 else 1.0)   # wanders, then holds
        frames.append(dz)
    runs = {}
    for fresh in (False, True):
        est = core.HierarchicalBank(model_bank, p_min=1e-6, threshold=1.0 - 1e-9, fresh_floor_levels=fresh)
        singles = [core.FilterModel(**{f: getattr(by_name[name], f) for f in fields}) for name in est.hypotheses]
        fb = core.FilterBank(singles, p_min=1e-6, fresh_floor_levels=fresh, h_output=model_bank.h_output)
        probabilities = []
        for dz in frames:
            est.step(z0 + dz, u0)
            fb.step(dz, np.zeros(u0.size))
            assert np.allclose(est.probabilities, fb.probabilities, rtol=1e-9, atol=1e-15)
            probabilities.append(np.asarray(est.probabilities).copy())
        runs[fresh] = np.array(probabilities)
        assert est.declarations == [] and est.level == 0
    assert not np.array_equal(runs[False], runs[True])


def test_the_footing_makes_the_failed_channel_a_likelihood_ratio():
    """filter_bank.h's common footing, leading term stripped: l_k - l_0 is the paper's stripped
    ratio of the two filters' densities of the other channels G (each whole density times
    sqrt|2 pi A_GG|) plus, on the failed channel, the exact log-likelihood ratio of the reading:
    the uniform density over W (first frame) against the no-failure filter's conditional normal
    of that reading given the others (SciPy)."""
    width = 7.5
    models = small_models(np.array([0.0, width, 0.0]))
    fb = core.FilterBank(models, p_min=1e-6)
    z = np.array([0.4, -0.7, 0.3])
    fb.update(z)
    r0, r1 = np.asarray(fb.residuals)[0], np.asarray(fb.residuals)[1]
    a0, a1 = np.asarray(models[0].a), np.asarray(models[1].a)
    g, j = [0, 2], 1
    gauss0 = stats.multivariate_normal(np.zeros(2), a0[np.ix_(g, g)])
    gauss1 = stats.multivariate_normal(np.zeros(2), a1[np.ix_(g, g)])
    stripped_g = (gauss1.logpdf(r1[g]) + 0.5 * np.linalg.slogdet(2 * np.pi * a1[np.ix_(g, g)])[1]
                  - gauss0.logpdf(r0[g]) - 0.5 * np.linalg.slogdet(2 * np.pi * a0[np.ix_(g, g)])[1])
    w = np.linalg.solve(a0[np.ix_(g, g)], a0[g, j])
    cond = stats.norm(w @ r0[g], np.sqrt(a0[j, j] - a0[j, g] @ w))
    ratio_f = stats.uniform(loc=r1[j] - 1.0, scale=width).logpdf(r1[j]) - cond.logpdf(r0[j])
    ll = fb.log_likelihoods
    assert ll[1] - ll[0] == pytest.approx(stripped_g + ratio_f, rel=1e-9, abs=1e-9)
