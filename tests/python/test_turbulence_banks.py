"""The turbulence bank set (design/turbulence_banks.py, core.TurbulenceBankSet): the artifact, one
set file, is checked by the C++ loader (its hash, every member bank, the fields), the estimator
option flies it and refuses a bank not of the set, the selector follows the turbulence in
closed loop (calm air: down; the light member holds from light to severe turbulence), a
failure whose onset coincides with a gust burst is declared, not absorbed, the set flies the
load-factor tempering its file carries unless one is given, and in severe turbulence that
tempering quiets a stabilator false declaration. The set the estimator flies (the executive's
member rule, cpp/executive/turbulence_set_bank.h) equals the set built here by that rule's
words, member by member, bit for bit."""
from __future__ import annotations

import shutil

import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import bank_estimator_settings, load_bank
from f16mmae.design.turbulence_banks import (CALM_BOUND, DWELL_S, FLOOR_P_MIN, FLOOR_RHO, MANEUVER_TEMPERING_G,
                                             MEMBER_LEVELS, MEMBER_P_MIN, TRIM_TIME_CONSTANT_S, BankSetError,
                                             load_set, set_path)
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import check
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure


@pytest.fixture(scope="module")
def bank_set():
    return load_set()   # designed into the cache on first use


@pytest.fixture()
def copy(bank_set, tmp_path):
    f = tmp_path / "set.f16set"
    shutil.copyfile(bank_set.path, f)
    return f


def test_the_set_is_six_input_members_in_rising_level(bank_set):
    assert bank_set.levels == MEMBER_LEVELS
    assert bank_set.path == set_path() and bank_set.path.suffix == ".f16set"
    for bank in bank_set.banks:
        assert (bank.nx, bank.nu, bank.nz) == (19, 6, 7)
        assert tuple(h.name for h in bank.hypotheses) == tuple(h.name for h in bank_set.banks[0].hypotheses)
    # the members differ where the design level enters: the residual covariance of NONE grows
    a = [np.trace(np.asarray(b.hypotheses[0].a)) for b in bank_set.banks]
    assert a == sorted(a) and a[0] < a[-1]
    assert load_set(bank_set.path).set_hash == bank_set.set_hash == bank_set.source.content_hash
    assert bank_set.trim_time_constant_s == TRIM_TIME_CONSTANT_S
    assert bank_set.maneuver_tempering_g == MANEUVER_TEMPERING_G == bank_set.source.maneuver_tempering_g == 1.0
    assert [b.estimator_settings["dwell_s"] for b in bank_set.banks] == [DWELL_S] * len(MEMBER_LEVELS) == [0.125] * 2
    assert Estimator(bank_set.banks[1], turbulence_banks=True).core_bank.dwell_s == 0.125
    label, path, bank = load_bank("turbulence")
    assert label == "turbulence" and path == bank_set.path and bank == bank_set.banks[bank_set.selector["start"]]


def test_a_damaged_or_invalid_set_is_refused_naming_the_field(bank_set, copy, tmp_path):
    data = bytearray(copy.read_bytes())
    data[-1] ^= 1
    copy.write_bytes(bytes(data))
    with pytest.raises(BankSetError, match=r"set\.f16set.*content hash mismatch"):
        load_set(copy)
    copy.write_bytes(b"{")
    with pytest.raises(BankSetError, match="not a turbulence bank set file"):
        load_set(copy)
    with pytest.raises(BankSetError, match="missing.f16set"):
        load_set(tmp_path / "missing.f16set")
    selector = {**bank_set.selector, "bounds": [-1.0] + bank_set.selector["bounds"][1:]}
    with pytest.raises(ValueError, match="bounds row 0 must be finite, positive and rising"):
        core.save_turbulence_set(tmp_path / "bad.f16set", list(bank_set.banks), levels=list(bank_set.levels),
                                 adapt_reference=list(bank_set.adapt_reference),
                                 trim_time_constant_s=list(bank_set.trim_time_constant_s), selector=selector)
    with pytest.raises(ValueError, match=r"maneuver_tempering_g must be in \[0, 100\] g \(0: off\), got -1"):
        core.save_turbulence_set(tmp_path / "bad.f16set", list(bank_set.banks), levels=list(bank_set.levels),
                                 adapt_reference=list(bank_set.adapt_reference),
                                 trim_time_constant_s=list(bank_set.trim_time_constant_s),
                                 selector=bank_set.selector, maneuver_tempering_g=-1.0)
    with pytest.raises(ValueError, match="unknown selector setting 'hold'"):
        core.save_turbulence_set(tmp_path / "bad.f16set", list(bank_set.banks), levels=list(bank_set.levels),
                                 adapt_reference=list(bank_set.adapt_reference),
                                 trim_time_constant_s=list(bank_set.trim_time_constant_s), selector={"hold": 1.0})
    assert not (tmp_path / "bad.f16set").exists()


def test_a_members_failure_model_applies_to_its_level_0_hypotheses_only(tmp_path, monkeypatch):
    """A member given ``constant=VEL`` with the duals ``complete``: its single VEL hypothesis
    reads an unknown constant over 2 x 3 TRIM_SIGMA (9.9 ft/s), and every other filter, the
    duals X+VEL included, is the all-``complete`` member's filter for filter."""
    from f16mmae.design import turbulence_banks
    from f16mmae.design.hypotheses import CONSTANT_HALF_WIDTH_SIGMAS, TRIM_SIGMA

    sets = {}
    for models in (("complete", "complete"), ("constant=VEL", "complete")):
        monkeypatch.setattr(turbulence_banks, "MEMBER_FAILURE_MODEL", models)
        monkeypatch.setattr(turbulence_banks, "DUAL_FAILURE_MODEL", "complete")
        sets[models[0]] = load_set(turbulence_banks.design_set(tmp_path / f"{models[0]}.f16set"))
    paper, split = sets["complete"], sets["constant=VEL"]
    for member in (0, 1):
        for h, g in zip(paper.banks[member].hypotheses, split.banks[member].hypotheses, strict=True):
            assert h.name == g.name
            assert np.array_equal(np.asarray(h.k), np.asarray(g.k)) and np.array_equal(np.asarray(h.a), np.asarray(g.a))
            width = np.asarray(g.uninformative_width)
            if member == 0 and g.name == "VEL":
                assert width[0] == pytest.approx(2 * CONSTANT_HALF_WIDTH_SIGMAS * TRIM_SIGMA["VEL"]) == pytest.approx(9.9)
                assert not width[1:].any() and np.asarray(g.uninformative_level_q)[0] > 0
            else:
                assert not width.any() and not np.asarray(g.uninformative_level_q).any(), g.name
    assert "level-1 (dual) hypotheses: complete" in split.banks[0].metadata
    assert split.banks[1].metadata == paper.banks[1].metadata


def test_the_core_refuses_invalid_selectors(bank_set):
    members = [core.HierarchicalBank(b, adapt_turbulence=True) for b in bank_set.banks]
    bounds, typical = bank_set.selector["bounds"], bank_set.selector["typical"]
    with pytest.raises(ValueError, match="bounds row 0 must be finite, positive and rising"):
        core.TurbulenceBankSet(members, [-1.0] + bounds[1:], typical)
    with pytest.raises(ValueError, match="without the turbulence adaptation"):
        core.TurbulenceBankSet([core.HierarchicalBank(bank_set.banks[0])] + members[1:], bounds, typical)
    with pytest.raises(ValueError, match="banks of one kind"):
        core.TurbulenceBankSet([members[0], core.HierarchicalBank(load_bank("tuned")[2], adapt_turbulence=True)],
                               [1.0, 0.5], [0.5, 0.5])


def test_the_option_needs_the_sets_bank():
    check({"turbulence_banks": True})
    with pytest.raises(ValueError, match="--tuning turbulence"):
        Estimator(load_bank("tuned")[2], turbulence_banks=True)


def _by_the_rule(bank_set, start_bank, given: dict):
    """The set as cpp/executive/turbulence_set_bank.h words its rule, built member by member from
    core.HierarchicalBank: the start member's recommended settings and ``given``; the adaptation
    on with each filter's power per channel it reads; the file's reference unless one is given;
    its trim tracking unless one is given; its load-factor tempering unless one is given."""
    members = []
    for bank, reference, trim in zip(bank_set.banks, bank_set.adapt_reference, bank_set.trim_time_constant_s):
        kw = {**bank_estimator_settings(start_bank), **given, "adapt_turbulence": True, "adapt_own_channels": True}
        kw.setdefault("adapt_reference", reference)
        if not given.get("trim_time_constant_s"):
            kw["trim_time_constant_s"] = trim
        if not given.get("maneuver_tempering_g"):
            kw["maneuver_tempering_g"] = bank_set.maneuver_tempering_g
        members.append(core.HierarchicalBank(bank, **kw))
    return core.TurbulenceBankSet(members, **bank_set.selector)


@pytest.mark.parametrize("given", [{}, {"adapt_reference": 0.9, "trim_time_constant_s": 60.0,
                                        "maneuver_tempering_g": 2.0}])
def test_the_set_flown_is_the_files_members_by_the_rule_bit_for_bit(bank_set, given):
    """Calm air, the set handing over from its light start member to the calm one, then a
    stuck left stabilator: the estimator's set (the set file through the binding) and the set
    built by the rule's words, fed the same frames, give the same probabilities and
    declarations on every frame."""
    bank = load_bank("turbulence")[2]
    frames = []
    est = Estimator(bank, turbulence_banks=True, **given)
    r = fly(Scenario(turbulence="none", duration_s=5.0, seed=3, feedback="raw", failures=(make_failure("LS", 3.0),)),
            bank, estimator=est, on_frame=lambda t, u, z, a: frames.append((t, u, z, a)))
    assert est.core_bank.switches >= 1 and r.declarations   # a handover and a declaration
    by_hand = _by_the_rule(bank_set, bank, given)
    declarations = []
    for i, (t, u, z, a) in enumerate(frames):
        by_hand.schedule(*a)
        declared = by_hand.update(z)
        by_hand.propagate(u)
        if declared is not None:
            declarations.append({"hypothesis": declared, "time_s": round(t, 9)})
        for name, p in zip(by_hand.hypotheses, by_hand.probabilities):
            assert r.probabilities[i, r.hypotheses.index(name)] == p, (i, name)
    assert declarations == r.declarations
    assert by_hand.switches == est.core_bank.switches and by_hand.active == est.core_bank.active


def _flight(level, seed, seconds, **scenario):
    bank = load_bank("turbulence")[2]
    est = Estimator(bank, turbulence_banks=True)
    active = []
    r = fly(Scenario(turbulence=level, duration_s=seconds, seed=seed, feedback="raw", **scenario), bank,
            estimator=est, on_frame=lambda *a: active.append(est.core_bank.active))
    return r, est, np.array(active)


def test_the_selector_follows_the_turbulence():
    r, est, active = _flight("severe", 3, 40.0)
    assert np.all(active == 1), "severe turbulence: the light member throughout ..."
    assert est.core_bank.turbulence_scale > 10, "... tempering its likelihoods"
    r, est, active = _flight("light", 3, 40.0)
    assert np.all(active == 1) and est.core_bank.switches == 0, "light turbulence: the light member throughout"
    r, est, active = _flight("none", 3, 40.0)
    assert active[-1] == 0 and est.core_bank.switches == 1, "calm air: the calm member, from the start's standby"
    assert np.argmax(active == 0) < 64 * 3
    assert r.declarations == []


def test_calm_air_goes_to_the_calm_member_by_its_own_rho_and_declares_nothing(bank_set):
    """The set's rule calmer_own_rho: in calm air the calm member, running beside the light one
    from frame 0 and reading its own rho below its own bound, takes over on the first frame the
    selector may (settle_s then hold_s), and the short flight declares nothing."""
    assert bank_set.selector["calmer_own_rho"] is True
    assert bank_set.selector["bounds"][0] == CALM_BOUND
    r, est, active = _flight("none", 5, 6.0)
    first = int(np.argmax(active == 0))
    assert active[first - 1] == 1 and np.all(active[first:] == 0) and est.core_bank.switches == 1
    # the first decision on the update that completes settle_s (frame settle - 1), the hold's
    # last frame hold - 1 frames later
    settle, hold = (round(64 * bank_set.selector[k]) for k in ("settle_s", "hold_s"))
    assert first == settle + hold - 2
    assert r.declarations == []


def test_the_light_members_floor_follows_its_rho(bank_set, tmp_path, monkeypatch):
    """The set's floor by rho (the shipped set's file with floor_rho 2.68 and the light member's
    floor 1e-6 below it): the light member, in force in light and in severe turbulence, has the
    raised floor while its own rho reads below floor_rho (light air) and its own floor above it
    (severe air) and before the selector's first decision (settle_s): the least probable
    hypothesis sits on the floor in force."""
    from f16mmae.design import turbulence_banks

    src = bank_set.source
    floor_rho, raised, own = 2.68, 1e-6, MEMBER_P_MIN[1]
    path = tmp_path / "floor.f16set"
    core.save_turbulence_set(path, src.members, levels=src.levels, adapt_reference=src.adapt_reference,
                             trim_time_constant_s=src.trim_time_constant_s,
                             selector={**src.selector, "floor_rho": floor_rho, "floor_p_min": [0.0, raised]},
                             maneuver_tempering_g=src.maneuver_tempering_g, adapt_gain=src.adapt_gain)
    monkeypatch.setattr(turbulence_banks, "set_path", lambda: path)   # the estimator's set
    assert load_set().selector["floor_p_min"] == [0.0, raised]
    settle = round(64 * bank_set.selector["settle_s"])
    for level, floor in (("light", raised), ("severe", own)):
        r, est, active = _flight(level, 3, 4.0)
        assert np.all(active == 1)
        assert (est.core_bank.turbulence_power_ratio < floor_rho) == (level == "light")
        early, last = r.probabilities[settle - 8], r.probabilities[-1]
        assert np.nanmin(early) == pytest.approx(own, rel=1e-6), level
        assert np.nanmin(last) == pytest.approx(floor, rel=1e-6), level
        assert r.declarations == []
    assert bank_set.selector["floor_rho"] == FLOOR_RHO and bank_set.selector["floor_p_min"] == list(FLOOR_P_MIN)


def test_the_set_flies_its_files_tempering_and_a_given_one_overrides_it():
    """Severe turbulence, the left stabilator stuck at 2 s of 6 s: the set as given (its file's
    tempering, 1 g) flies exactly as the set with --maneuver-tempering 1 given, and differently
    from the set given another (the tempering acts on this flight)."""
    bank = load_bank("turbulence")[2]
    sc = Scenario(turbulence="severe", duration_s=6.0, seed=3, feedback="raw", failures=(make_failure("LS", 2.0),))
    probabilities = {}
    for given in (None, 1.0, 4.0):
        options = {} if given is None else {"maneuver_tempering_g": given}
        probabilities[given] = fly(sc, bank, estimator=Estimator(bank, turbulence_banks=True, **options)).probabilities
    assert np.array_equal(probabilities[None], probabilities[1.0], equal_nan=True)   # NaN: not on line
    assert np.nanmax(np.abs(probabilities[None] - probabilities[4.0])) > 1e-3


def test_a_failure_with_a_gust_burst_is_declared_not_absorbed():
    """The failure and a burst of severe turbulence begin together in light turbulence: the
    selector is frozen while the failure rises, so the bank in force declares it."""
    fail = make_failure("LS", 5.0, "complete")
    r, est, active = _flight("light", 4, 12.0, gust_burst="severe@5+7", failures=(fail,))
    assert r.declarations and r.declarations[0]["hypothesis"] == "LS"
    assert r.declarations[0]["time_s"] > 5.0
    assert r.final_hypothesis == "LS"
    assert est.core_bank.frozen_frames > 0


@pytest.mark.slow
def test_the_load_factor_tempering_quiets_a_severe_stabilator_false_declaration():
    """Severe turbulence, the pilot holding (the soak's ``hold`` profile; campaign seed 7's first
    flight): a gust takes the angle of attack from 8 to 15 deg near 238 s, where the linear
    models no longer hold, and the set barely tempered (n_ref 100 g given) declares RS falsely
    for 3.5 s; with the set file's load-factor tempering at 1 g (cpp/f16mmae/maneuver_kinematics.h)
    it declares nothing. Flown with the fixed dither (the adaptive one, the set's default, moves
    the flaperons' line and the barely tempered set then declares nothing here either)."""
    from f16mmae.campaign.soak.campaign import profile

    bank = load_bank("turbulence")[2]
    sc = Scenario(turbulence="severe", duration_s=243.0, seed=1713771395, feedback="reconfigure",
                  maneuvers=profile("hold", bank.mach, bank.alt_ft)[0])
    plain = fly(sc, bank, estimator=Estimator(bank, turbulence_banks=True, fixed_dither=True,
                                              maneuver_tempering_g=100.0))
    assert [d["hypothesis"] for d in plain.declarations] == ["RS", "NONE"]
    assert 236.0 < plain.declarations[0]["time_s"] < 240.0
    tempered = fly(sc, bank, estimator=Estimator(bank, turbulence_banks=True, fixed_dither=True))
    assert tempered.declarations == []
