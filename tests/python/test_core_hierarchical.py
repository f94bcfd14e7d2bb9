"""core.HierarchicalBank and core.Declarer on synthetic model banks designed like the real
one (B column / H row removed, gains from SciPy's DARE) and flown against a linear truth:
a single failure then a dual, back-out, absolute-signal handling, the F-16-sized fixed
bank's level-1 set (names.level1_hypotheses), and boundary errors."""
from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are

from f16mmae import core, names

RATE_HZ = 64.0


def plant(seed, n, p, m, var=1e-3):
    rng = np.random.default_rng(seed)
    phi = rng.standard_normal((n, n))
    phi *= 0.95 / max(abs(np.linalg.eigvals(phi)))
    return dict(phi=phi, bd=rng.standard_normal((n, p)), h=rng.standard_normal((m, n)), q=var * np.eye(n),
                r=var * np.eye(m))


def matrices(pl, actuators, sensors, failed):
    bd, h = pl["bd"].copy(), pl["h"].copy()
    for c in failed:
        if c in actuators:
            bd[:, actuators.index(c)] = 0.0
        if c in sensors:
            h[sensors.index(c), :] = 0.0
    return bd, h


def model_bank(pl, actuators, sensors, u_trim, z_trim):
    comps = list(actuators) + list(sensors)
    hyp_names = ["NONE"] + comps + [f"{a}+{b}" for a, b in combinations(comps, 2)]
    hyps = []
    for name in hyp_names:
        bd, h = matrices(pl, actuators, sensors, [] if name == "NONE" else name.split("+"))
        p_prior = solve_discrete_are(pl["phi"].T, h.T, pl["q"], pl["r"])
        a = h @ p_prior @ h.T + pl["r"]
        a = 0.5 * (a + a.T)
        hyps.append((name, dict(phi=pl["phi"], bd=bd, h=h, k=p_prior @ h.T @ np.linalg.inv(a), a=a)))
    return core.ModelBank(hyps, state_names=[f"x{i}" for i in range(pl["phi"].shape[0])], input_names=list(actuators),
                          measurement_names=list(sensors), frame_rate_hz=RATE_HZ, u_trim=u_trim, z_trim=z_trim,
                          h_output=pl["h"])


def fly(pl, actuators, sensors, bank, failures, frames, seed):
    """Absolute (z, u) frames; failures: (component, first frame, end frame)."""
    rng = np.random.default_rng(seed)
    x = np.zeros(pl["phi"].shape[0])
    zs, us = [], []
    p = len(actuators)
    for i in range(frames):
        failed = [c for c, a, b in failures if a <= i < b]
        bd, h = matrices(pl, actuators, sensors, failed)
        zs.append(h @ x + rng.multivariate_normal(np.zeros(len(sensors)), pl["r"]) + bank.z_trim)
        u = np.sin(2 * np.pi * (0.7 + 0.37 * np.arange(p)) * i / RATE_HZ + np.arange(p))
        us.append(u + bank.u_trim)
        x = pl["phi"] @ x + bd @ u + rng.multivariate_normal(np.zeros(len(x)), pl["q"])
    return zs, us


ACT, SEN = ("U1", "U2"), ("Z1", "Z2", "Z3")


@pytest.fixture(scope="module")
def small():
    pl = plant(21, 3, 2, 3)
    return pl, model_bank(pl, ACT, SEN, np.array([0.1, -0.2]), np.array([10.0, 1.0, -3.0]))


def test_single_then_dual_failure(small):
    pl, mb = small
    hb = core.HierarchicalBank(mb)
    assert not hb.fixed_size and hb.level == 0 and hb.declared == "NONE"
    assert hb.hypotheses == ("NONE", "U1", "U2", "Z1", "Z2", "Z3")
    zs, us = fly(pl, ACT, SEN, mb, [("U1", 64, 10**9), ("Z3", 320, 10**9)], 640, seed=2)
    events = [(i, hb.step(z, u)) for i, (z, u) in enumerate(zip(zs, us))]
    events = [(i, d) for i, d in events if d is not None]
    assert [d for _, d in events] == ["U1", "U1+Z3"]
    decl = hb.declarations
    assert [(d["hypothesis"], d["level"]) for d in decl] == [("U1", 0), ("U1+Z3", 1)]
    assert [d["frame"] for d in decl] == [i for i, _ in events]
    assert 64 + 15 <= decl[0]["frame"] < 128 and 320 + 15 <= decl[1]["frame"] < 384
    assert decl[0]["time_s"] == decl[0]["frame"] / RATE_HZ
    assert hb.level == 1 and hb.level1_failure == "U1" and hb.declared == "U1+Z3"
    assert hb.hypotheses == ("NONE", "U1", "U1+U2", "U1+Z1", "U1+Z2", "U1+Z3")
    p = hb.probabilities
    assert abs(p.sum() - 1) < 1e-12 and np.argmax(p) == 5


def test_back_out_when_none_wins_at_level_one(small):
    pl, mb = small
    hb = core.HierarchicalBank(mb, declarer=core.Declarer(threshold=0.9, dwell_s=0.25))
    zs, us = fly(pl, ACT, SEN, mb, [("Z2", 64, 256)], 512, seed=3)
    for z, u in zip(zs, us):
        hb.step(z, u)
    assert [(d["hypothesis"], d["level"]) for d in hb.declarations] == [("Z2", 0), ("NONE", 1)]
    assert hb.level == 0 and hb.level1_failure is None and hb.declared == "NONE"
    hb.reset()
    assert hb.declarations == [] and hb.frames == 0


def test_signals_are_absolute(small):
    pl, mb = small
    hb = core.HierarchicalBank(mb)
    level0 = [dict(zip(("phi", "bd", "h", "k", "a"), (m.phi, m.bd, m.h, m.k, m.a))) for m in mb.hypotheses[:6]]
    plain = core.FilterBank([core.FilterModel(**m) for m in level0], h_output=mb.h_output)
    zs, us = fly(pl, ACT, SEN, mb, [], 100, seed=4)
    for z, u in zip(zs, us):
        hb.step(z, u)
        plain.step(z - mb.z_trim, u - mb.u_trim)
        np.testing.assert_allclose(hb.probabilities, plain.probabilities, atol=1e-12)
        np.testing.assert_allclose(hb.z_hat, plain.z_hat + mb.z_trim, atol=1e-12)
        np.testing.assert_allclose(hb.z_hat_perturbation, plain.z_hat, atol=1e-12)
        np.testing.assert_allclose(hb.residuals, plain.residuals, atol=1e-12)
    assert hb.declarations == []


def test_rejected_frames_and_boundary_errors(small):
    pl, mb = small
    hb = core.HierarchicalBank(mb, threshold=0.95, dwell_s=0.5)
    assert hb.dwell_frames == 32 and hb.threshold == 0.95
    assert hb.step([np.nan, 0.0, 0.0], [0.0, 0.0]) is None
    assert hb.rejected_frames == 1 and hb.frames == 1
    with pytest.raises(ValueError, match=r"z must have shape \(3,\), got \(7,\)"):
        hb.update(np.zeros(7))
    with pytest.raises(ValueError, match=r"u must have shape \(2,\), got \(3,\)"):
        hb.step(np.zeros(3), np.zeros(3))
    assert hb.frames == 1  # a bad u refuses the whole frame
    with pytest.raises(ValueError, match=r"threshold must be in \(0.5, 1\)"):
        core.HierarchicalBank(mb, threshold=0.3)
    with pytest.raises(ValueError, match="declarer must be a core.Declarer"):
        core.HierarchicalBank(mb, declarer=0.9)
    hyps = [(h.name, h) for h in mb.hypotheses if h.name != "U2+Z1"]
    partial = core.ModelBank(hyps, state_names=mb.state_names, input_names=mb.input_names,
                             measurement_names=mb.measurement_names, frame_rate_hz=RATE_HZ)
    with pytest.raises(ValueError, match=r"no dual hypothesis 'U2\+Z1'"):
        core.HierarchicalBank(partial)


def test_declarer_binding():
    d = core.Declarer(dwell_s=3 / 64)
    assert d.dwell_frames == 3 and d.current == 0
    p = np.array([0.04, 0.95, 0.01])
    assert [d.update(p) for _ in range(4)] == [None, None, 1, None]
    assert d.current == 1
    with pytest.raises(ValueError, match="dwell_s"):
        core.Declarer(dwell_s=-1.0)


def test_f16_sized_bank_is_fixed_size_and_brings_on_the_named_level1_bank():
    pl = plant(31, names.NX, names.NU, names.NZ)
    mb = model_bank(pl, names.ACTUATORS, names.SENSORS, np.full(5, -0.03),
                    np.array([414.8, 0.14, 0.0, 1.0, 0.0, 0.0, 0.0]))
    assert mb.hypothesis_names == names.ALL_HYPOTHESES
    hb = core.HierarchicalBank(mb)
    assert hb.fixed_size and hb.hypotheses == names.SINGLE_HYPOTHESES
    zs, us = fly(pl, names.ACTUATORS, names.SENSORS, mb, [("PIT", 64, 10**9)], 256, seed=5)
    for z, u in zip(zs, us):
        hb.step(z, u)
    assert [d["hypothesis"] for d in hb.declarations] == ["PIT"]
    assert hb.hypotheses == names.level1_hypotheses("PIT")
