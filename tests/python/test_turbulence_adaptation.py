"""The turbulence adaptation through the binding and the loop, and the truth's gust burst:
off is the bank as designed (bit for bit), on its scale is recorded per frame and rises with
the turbulence, a gust burst flies the same on both truth engines and in the whole-C++ loop,
and a failure whose onset coincides with a gust burst is still declared."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae import core
from f16mmae.banks import load_bank
from f16mmae.campaign.engine.config import CampaignConfig
from f16mmae.campaign.engine.drilldown import reproduce_command
from f16mmae.cli.main import main as cli_main
from f16mmae.loop.flight import fly
from f16mmae.truth import Scenario, fly_raw, parse_fail
from f16mmae.truth.turbulence import GustBurst

ADAPT = {"adapt_turbulence": True}


@pytest.fixture(scope="module")
def bank():
    return load_bank("tuned")[2]


def _scenario(bank, **kw) -> Scenario:
    return Scenario(mach=float(bank.mach), alt_ft=float(bank.alt_ft), **kw)


def test_gust_burst_parses_checks_and_round_trips():
    b = GustBurst.parse("Severe@3+2.5")
    assert (b.level, b.start_s, b.duration_s) == ("severe", 3.0, 2.5)
    assert b.schedule("light", 64.0) == [(192, "severe"), (352, "light")]
    for bad, what in (("severe", "LEVEL@START"), ("gale@1+1", "valid: none, light"), ("light@-1+1", "start_s"),
                      ("light@1+0", "duration_s")):
        with pytest.raises(ValueError, match=what):
            GustBurst.parse(bad)
    sc = Scenario(duration_s=4.0, gust_burst="moderate@1+1")
    assert Scenario.from_dict(sc.to_dict()) == sc
    assert "gust_burst" not in Scenario(duration_s=4.0).to_dict()   # records without a burst are unchanged
    with pytest.raises(ValueError, match="after the end"):
        Scenario(duration_s=4.0, gust_burst="moderate@5+1")
    with pytest.raises(ValueError, match="level, start_s, duration_s"):
        Scenario.from_dict({"gust_burst": {"level": "light", "start": 1.0, "duration_s": 1.0}})


def test_a_gust_burst_flies_the_same_on_both_engines_and_acts_only_from_its_start():
    sc = Scenario(duration_s=2.0, seed=41, turbulence="light", feedback="raw", gust_burst="severe@0.5+0.75")
    ref, _ = fly_raw(sc, engine="python")
    cpp, _ = fly_raw(sc, engine="cpp")
    for k in ("z", "z_ideal", "state", "surface_rad"):
        assert np.array_equal(ref.truth_log[k], cpp.truth_log[k]), k
    plain, _ = fly_raw(Scenario(duration_s=2.0, seed=41, turbulence="light", feedback="raw"), engine="cpp")
    z, z0 = cpp.truth_log["z_ideal"], plain.truth_log["z_ideal"]
    first = 32  # 0.5 s at 64 Hz: its JSBSim steps are the first in severe turbulence
    assert np.array_equal(z[: first + 1], z0[: first + 1])
    assert not np.array_equal(z[first + 2:], z0[first + 2:])


def test_off_is_the_bank_as_designed_and_on_records_a_rising_scale(bank):
    sc = _scenario(bank, duration_s=20.0, seed=42, turbulence="moderate")
    plain = fly(sc, bank)
    off = fly(sc, bank, estimator_options={"adapt_turbulence": False})
    assert np.array_equal(plain.probabilities, off.probabilities, equal_nan=True)
    assert plain.declarations == off.declarations
    assert np.all(plain.turbulence_scale == 1.0)
    on = fly(sc, bank, estimator_options=ADAPT)
    assert on.estimator_settings["adapt_turbulence"] is True
    s = on.turbulence_scale
    assert s.shape == (len(on.time_s),) and np.all(s >= 1.0)
    calm = fly(_scenario(bank, duration_s=20.0, seed=42, turbulence="none"), bank, estimator_options=ADAPT)
    assert s[-64:].mean() > 1.5 * calm.turbulence_scale[-64:].mean()


def test_the_whole_cpp_loop_records_what_the_per_frame_loop_does_through_a_burst(bank):
    sc = _scenario(bank, duration_s=6.0, seed=43, turbulence="light", gust_burst="severe@2.0+1.5",
                   failures=(parse_fail("LF@2.0"),))
    whole = fly(sc, bank, engine="cpp", estimator_options=ADAPT)
    for engine in ("cpp", "python"):
        frames = fly(sc, bank, engine=engine, estimator_options=ADAPT, on_frame=lambda *frame: None)
        assert frames.declarations == whole.declarations
        assert np.array_equal(frames.probabilities, whole.probabilities, equal_nan=True)
        assert np.array_equal(frames.turbulence_scale, whole.turbulence_scale)


def test_a_failure_at_the_onset_of_a_gust_burst_is_declared_not_absorbed(bank):
    """Light turbulence, then moderate gusts from 3 s, when the left flaperon fails: the
    adaptation raises its scale with the gusts, but the failed flaperon's filter fits the
    failure, so the scale (from the minimum over the hypotheses) is what the gusts alone make
    of it -- within 10 % of the same flight without the failure until the declaration -- and
    LF is declared and stays the answer."""
    kw = dict(duration_s=8.0, seed=44, turbulence="light", gust_burst="moderate@3.0+5.0")
    r = fly(_scenario(bank, failures=(parse_fail("LF@3.0"),), **kw), bank, estimator_options=ADAPT)
    calm = fly(_scenario(bank, **kw), bank, estimator_options=ADAPT)
    assert [d["hypothesis"] for d in r.declarations] == ["LF"] and not calm.declarations
    t_d = r.declarations[0]["time_s"]
    assert 3.0 < t_d <= 5.0
    upto = int(t_d * 64)
    ratio = r.turbulence_scale[192:upto] / calm.turbulence_scale[192:upto]
    assert np.all(np.abs(ratio - 1.0) < 0.1), ratio.max()
    assert calm.turbulence_scale[upto] > 2.0   # the gusts did raise the scale


def test_bad_adaptation_settings_are_refused_by_name(bank):
    for kw, what in (({"adapt_time_constant_s": 0.0}, "adapt_time_constant_s"),
                     ({"adapt_scale_min": 0.0}, "adapt_scale_min"),
                     ({"adapt_scale_min": 2.0, "adapt_scale_max": 1.0}, "adapt_scale_max")):
        with pytest.raises(ValueError, match=what):
            core.HierarchicalBank(bank, adapt_turbulence=True, **kw)
    hb = core.HierarchicalBank(bank)
    assert hb.adapt_turbulence is False and hb.turbulence_scale == 1.0


def test_the_options_reach_the_campaign_the_reproduce_command_and_the_run(tmp_path, capsys, bank):
    cfg = CampaignConfig(estimator={"adapt_turbulence": True})
    assert cfg.estimator_options() == {"adapt_turbulence": True}
    sc = _scenario(bank, duration_s=2.0, seed=45, turbulence="light", gust_burst="severe@1.0+0.5")
    cmd = reproduce_command(sc.to_dict(), "tuned", {"adapt_turbulence": True})
    assert cmd.endswith("--gust-burst severe@1.0+0.5 --bank tuned --adapt-turbulence")
    assert cli_main(cmd.split()[1:] + ["--out", str(tmp_path / "run")]) == 0
    header = (tmp_path / "run" / "probabilities.csv").read_text().splitlines()[0]
    assert header.endswith(",turbulence_scale")
    assert cli_main(["run", "--duration", "1", "--gust-burst", "severe@x+1"]) == 2
    assert "--gust-burst" in capsys.readouterr().err
