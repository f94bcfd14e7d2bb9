"""The turbulence adaptation's running start (``--adapt-running-start``,
cpp/f16mmae/turbulence_adaptation.h): the core's power ratio is the plain mean of the frames'
minimum forms from the start, where without it it rises from the reference; a scheduled design
calibrated with it (``design --schedule --adapt-running-start``) records and recommends it, and
the estimator, ``hil`` and ``replay`` fly a recommending file with it
(``estimator_options.scheduled_defaults``)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.banks import load_bank
from f16mmae.cli.main import main
from f16mmae.design.bank import design_bank, to_model_bank
from f16mmae.loop.estimator import Estimator
from f16mmae.loop.estimator_options import bank_defaults, check, recommends_running_start, scheduled_defaults


def test_the_core_s_power_ratio_is_the_plain_mean_from_the_start():
    """The level-0 filters run as a plain core.FilterBank give each frame's min_k q_k / m; the
    hierarchical bank's rho with the running start is their mean so far."""
    design = design_bank(0.4, 20_000.0, "tuned")
    bank = to_model_bank(design)
    fb = core.FilterBank([core.FilterModel(phi=f.model.phi, bd=f.model.bd, h=f.model.h, k=f.gains.k, a=f.gains.a)
                          for f in design.filters if f.name in names.SINGLE_HYPOTHESES])
    rng = np.random.default_rng(3)
    dz = 0.01 * rng.standard_normal((40, names.NZ)) * np.sqrt(np.diag(design.filters[0].gains.a))
    du = np.zeros((40, bank.nu))
    rs = core.HierarchicalBank(bank, adapt_turbulence=True, adapt_running_start=True)
    plain = core.HierarchicalBank(bank, adapt_turbulence=True)
    xs = []
    for i in range(40):
        rs.step(np.asarray(bank.z_trim) + dz[i], np.asarray(bank.u_trim) + du[i])
        plain.step(np.asarray(bank.z_trim) + dz[i], np.asarray(bank.u_trim) + du[i])
        fb.update(dz[i])
        xs.append(float(np.min(fb.quadratic_forms)) / names.NZ)
        fb.propagate(du[i])
        assert rs.turbulence_power_ratio == pytest.approx(np.mean(xs), rel=1e-9), i
    # without it the ratio is still on its way from the reference (0.6) after 40 frames of 320
    assert abs(plain.turbulence_power_ratio - np.mean(xs)) > 0.5 * abs(0.6 - np.mean(xs))


def test_scheduled_defaults_turn_it_on_where_the_file_recommends_it():
    given = {"adapt_turbulence": True}
    on = scheduled_defaults(given, True, running_start=True)
    assert on["adapt_running_start"] is True and scheduled_defaults(on, True, True) == on   # twice as once
    assert "adapt_running_start" not in scheduled_defaults(given, True)           # not recommended
    assert "adapt_running_start" not in scheduled_defaults({}, True, True)        # no adaptation
    assert "adapt_running_start" not in scheduled_defaults(given, False, True)    # one point
    sets = {"adapt_turbulence": True, "turbulence_banks": True}
    assert scheduled_defaults(sets, True, True) == sets                           # a bank set: its own rule
    with pytest.raises(ValueError, match="--adapt-running-start applies with --adapt-turbulence only"):
        check({"adapt_running_start": True})


def _design(tmp_path_factory, *extra):
    out = tmp_path_factory.mktemp("rs") / "one.f16sched"
    assert main(["design", "--schedule", "mach=0.5,alt=20000", *extra, "--workers", "1", "--out", str(out)]) == 0
    return core.load_bank(out)


def test_a_design_calibrated_with_it_records_and_recommends_it(tmp_path_factory):
    rs, plain = _design(tmp_path_factory, "--adapt-running-start"), _design(tmp_path_factory)
    meta, plain_meta = (json.loads(b.schedule["metadata"]) for b in (rs, plain))
    assert meta["adapt_running_start"] is True and "adapt_running_start" not in plain_meta
    assert " --adapt-running-start" in meta["command"] and "running" not in plain_meta["command"]
    assert recommends_running_start(rs) and not recommends_running_start(plain)
    assert not recommends_running_start(load_bank("tuned")[2])   # one point
    assert Estimator(rs, adapt_turbulence=True).settings["adapt_running_start"] is True
    assert "adapt_running_start" not in Estimator(plain, adapt_turbulence=True).settings
    assert "adapt_running_start" not in Estimator(rs).settings   # no adaptation asked
    given = {"adapt_turbulence": True}   # hil, replay and the estimator: one rule for a bank
    # both calibrated designs carry the calm-air reference (schedule format 4)
    assert bank_defaults(given, rs) == scheduled_defaults(given, True, True, calm_reference=True)
    assert bank_defaults(given, plain) == scheduled_defaults(given, True, False, calm_reference=True)
    assert bank_defaults(given, load_bank("tuned")[2]) == given
    # the node's floors and references were bounded on flights flown with it: the calibration's
    # mean scales (candidates [p_min, reference, peak, s, met]) are not the plain start's
    node, plain_node = meta["nodes"][0], plain_meta["nodes"][0]
    assert node["knobs"] == plain_node["knobs"]   # the same stage 1
    assert [c[3] for c in node["candidates"]] != [c[3] for c in plain_node["candidates"]]
