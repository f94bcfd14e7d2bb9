"""Scenarios are plain data: TOML in, dict out and back; bad scenarios are refused with
messages that name the bad value and the valid choices."""
from __future__ import annotations

import pytest

from f16mmae.truth import DitherSpec, FailureSpec, Scenario
from f16mmae.truth.scenario import EXAMPLES_DIR, example


def test_defaults_are_the_papers_nominal_point():
    sc = Scenario()
    assert (sc.mach, sc.alt_ft, sc.seed, sc.feedback, sc.ari) == (0.4, 20_000.0, 1, "mmae", True)
    assert sc.dither.enabled and sc.failures == ()


@pytest.mark.parametrize("path", sorted(EXAMPLES_DIR.glob("*.toml")), ids=lambda p: p.stem)
def test_example_scenarios_load_and_round_trip(path):
    sc = Scenario.from_toml(path)
    assert Scenario.from_dict(sc.to_dict()) == sc


def test_toml_text_with_strings_and_tables():
    sc = Scenario.from_toml(
        'mach = 0.5\nalt_ft = 15000\nturbulence = "Moderate"\nseed = 4\nfailures = ["rf@2:stuck"]\n'
        '[[failure]]\nname = "az"\ntime_s = 1.5\nmode = "bias"\nvalue = 0.2\n'
        '[dither]\nenabled = false\n')
    assert sc.turbulence == "moderate" and not sc.dither.enabled
    assert sc.failures == (FailureSpec("AZ", 1.5, "bias", 0.2), FailureSpec("RF", 2.0, "stuck"))
    assert example("single_ls").failures == (FailureSpec("LS", 3.0, "complete"),)


def test_dict_layout_of_the_campaign_records():
    d = {"mach": 0.4, "alt_ft": 20000.0, "turbulence": "light", "dither": True, "duration_s": 6.0,
         "seed": 3, "feedback": "mmae", "failures": [{"name": "PIT", "time_s": 3.0, "mode": "complete"}]}
    sc = Scenario.from_dict(d)
    assert sc.failures == (FailureSpec("PIT", 3.0),) and sc.dither == DitherSpec()


@pytest.mark.parametrize("kw,words", [
    ({"mach": 0.9}, ["mach 0.9", "0.3-0.8"]),
    ({"alt_ft": 50_000}, ["alt_ft", "5000-35000"]),
    ({"seed": 0}, ["seed", ">= 1"]),
    ({"seed": -3}, ["seed", ">= 1"]),
    ({"seed": 1.5}, ["seed"]),
    ({"turbulence": "extreme"}, ["extreme", "none, light, moderate, severe"]),
    ({"feedback": "kalman"}, ["kalman", "mmae, raw"]),
    ({"duration_s": 0}, ["duration_s"]),
    ({"duration_s": 2.0, "failures": (FailureSpec("LS", 3.0),)}, ["after the end"]),
    ({"failures": (FailureSpec("LS", 1.0), FailureSpec("LS", 2.0))}, ["more than once"]),
    ({"ari": "yes"}, ["ari", "true or false"]),
])
def test_bad_scenarios_are_refused(kw, words):
    with pytest.raises(ValueError) as exc:
        Scenario(**kw)
    for w in words:
        assert w in str(exc.value)


@pytest.mark.parametrize("text,words", [
    ('machh = 0.4', ["unknown scenario key", "machh", "mach, alt_ft"]),
    ('failures = ["QQ@1"]', ["unknown failure name", "QQ", "VEL"]),
    ('failures = ["LS@-2"]', [">= 0"]),
    ('failures = ["LS@2:wobble"]', ["wobble", "complete, stuck, hardover, loss"]),
    ('[dither]\nfreq = 3', ["unknown dither key", "freq"]),
    ('[dither]\namplitude_deg = [1, 1]', ["5 values"]),
    ('[[failure]]\nname = "LS"', ["needs name and time_s"]),
    ('mach = ', ["not valid TOML"]),
])
def test_bad_toml_is_refused(text, words):
    with pytest.raises(ValueError) as exc:
        Scenario.from_toml(text + "\n")
    for w in words:
        assert w in str(exc.value)


def test_missing_file_is_named(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        Scenario.from_toml(tmp_path / "nope.toml")
    with pytest.raises(ValueError, match="nominal"):
        example("nope")
