"""The declaration dwell a cover bank recommends (design/dwell.py), checked against the core's
own declarer: a dwell declares a failure in the calibration flights exactly when its frames do
not exceed the longest excursion the calibration measured."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from f16mmae import core, names
from f16mmae.cli.main import main
from f16mmae.design import bank, dwell
from f16mmae.design.flights import fly_closed_loop
from f16mmae.design.model import linearize_truth
from f16mmae.design.tuning import TUNINGS_DIR, load_tuning

#: No-failure tuning flights in which the cover bank's free flaperon rises above the threshold
#: for 20 frames (seed 6) and one in which nothing does (seed 3).
SEEDS = (6, 3)


@pytest.fixture(scope="module")
def cover_bank(tmp_path_factory):
    tun = dataclasses.replace(load_tuning("tuned"), name="tuned-cover", failure_model="cover")
    d = bank.design_bank(tuning=tun, linearized=linearize_truth(0.4, 20_000.0))
    return d, bank.write_bank(d, tmp_path_factory.mktemp("dwell") / "cover.f16bank")


@pytest.fixture(scope="module")
def flights():
    return [fly_closed_loop(0.4, 20_000.0, seed=s) for s in SEEDS]


def declares(model_bank, flights, dwell_s: float) -> bool:
    """Whether the estimator the bank makes declares a failure in any of the flights."""
    est = core.HierarchicalBank(model_bank, **{**model_bank.estimator_settings, "dwell_s": dwell_s})
    u_trim, z_trim = np.asarray(model_bank.u_trim), np.asarray(model_bank.z_trim)
    for fl in flights:
        est.reset()
        for u, z in zip(fl.u + u_trim, fl.z + z_trim):
            if est.step(z, u) is not None:
                return True
    return False


def test_a_dwell_declares_exactly_when_it_is_no_longer_than_the_longest_excursion(cover_bank, flights):
    _, mb = cover_bank
    per = dwell.longest_excursion(mb, flights)
    longest = max(n for n, _ in per)
    assert longest > 0, "the calibration flights should hold a failure hypothesis above the threshold"
    assert per[1][0] < longest
    # per hypothesis: each flight's longest is its largest hypothesis' stretch, failures only
    each = dwell.excursions(mb, flights)
    assert [max(e.values(), default=0) for e in each] == [n for n, _ in per]
    assert all(h in names.SINGLE_HYPOTHESES[1:] and n > 0 for e in each for h, n in e.items())
    assert all(e.get(h, 0) == n for e, (n, h) in zip(each, per) if n > 0)
    rate = float(mb.frame_rate_hz)
    assert declares(mb, flights, longest / rate)
    assert not declares(mb, flights, (longest + 1) / rate)


def test_the_recommended_dwell_is_the_smallest_candidate_the_flights_do_not_fill(cover_bank, flights):
    _, mb = cover_bank
    longest = max(n for n, _ in dwell.longest_excursion(mb, flights))
    rate = float(mb.frame_rate_hz)
    below, above = longest / rate, (longest + 1) / rate
    res = dwell.calibrated_dwell(mb, flights, candidates=(above, below, above + 1.0))
    assert res["dwell_s"] == pytest.approx(above) and res["bound_met"]
    assert res["longest_frames"] == longest and res["hypothesis"] in names.SINGLE_HYPOTHESES[1:]
    none_fit = dwell.calibrated_dwell(mb, flights, candidates=(below / 2, below))
    assert none_fit["dwell_s"] == pytest.approx(below) and not none_fit["bound_met"]


def test_the_design_writes_its_calibrated_dwell(cover_bank, flights, tmp_path):
    d, mb = cover_bank
    calibrated, res = dwell.with_calibrated_dwell(d, flights)
    assert calibrated.tuning.estimator["dwell_s"] == res["dwell_s"]
    assert {k: v for k, v in calibrated.tuning.estimator.items() if k != "dwell_s"} == \
        {k: v for k, v in d.tuning.estimator.items() if k != "dwell_s"}
    written = bank.write_bank(calibrated, tmp_path / "c.f16bank")
    assert written.dwell_s == res["dwell_s"]
    assert json.loads(written.metadata)["tuning"]["estimator"]["dwell_s"] == res["dwell_s"]
    assert not declares(written, flights, written.dwell_s)


def test_design_cli_recommends_a_cover_banks_dwell_and_keeps_a_tunings_own(capsys, tmp_path):
    out = tmp_path / "cover.f16bank"
    assert main(["design", "--failure-model", "cover", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    mb = core.load_bank(str(out))
    assert f"recommended dwell {mb.dwell_s:g} s" in text
    assert mb.dwell_s in dwell.DWELL_CANDIDATES_S
    flights = [fly_closed_loop(0.4, 20_000.0, seed=s) for s in range(1, 9)]
    assert mb.dwell_s == dwell.calibrated_dwell(mb, flights)["dwell_s"]
    # a cover tuning that recommends its own dwell keeps it
    own = tmp_path / "own.toml"
    src = (TUNINGS_DIR / "tuned.toml").read_text()
    own.write_text(src.replace('name = "tuned"', 'name = "own"\nfailure_model = "cover"')
                   .replace("dwell_s = 0.25", "dwell_s = 0.75"))
    out2 = tmp_path / "own.f16bank"
    assert main(["design", "--tuning", str(own), "--out", str(out2)]) == 0
    assert "recommended dwell" not in capsys.readouterr().out
    assert core.load_bank(str(out2)).dwell_s == 0.75
