"""The bank's recommended evidence dwell per hypothesis (bank format 4: each hypothesis'
``dwell_nats``; cpp/f16mmae/declarer.h): the shipped bank carries the tuning's table, a file
round-trips it, bad tables are refused by name, an explicit ``--dwell-nats`` or
``--dwell-nats-per-hypothesis`` overrides it, and mmae-daemon and the in-process estimator fly
it alike."""
from __future__ import annotations

import tomllib

import pytest

from f16mmae import core
from f16mmae.banks import bank_estimator_settings, load_bank
from f16mmae.design.tuning import TUNINGS_DIR, TuningError, tuning_from_dict
from f16mmae.truth import Scenario
from f16mmae.truth.failures import make_failure

from daemon_support import ready_line

from test_bank_file import make_bank


def _committed_table() -> dict[str, float]:
    """tuned.toml's [estimator] dwell_nats_per_hypothesis, read with tomllib alone."""
    return tomllib.loads((TUNINGS_DIR / "tuned.toml").read_text())["estimator"]["dwell_nats_per_hypothesis"]


def test_the_shipped_bank_reads_back_the_tunings_table():
    bank = load_bank("tuned")[2]
    table = _committed_table()
    assert set(table) == {"LS", "RS", "LF", "RF", "RUD", "VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY"}
    got = {h.name: h.dwell_nats for h in bank.hypotheses}
    for name, n in got.items():   # every hypothesis: the table's N_k, 0 where it names none
        assert n == table.get(name, 0.0), name
    assert got["NONE"] == 0.0 and got["RUD"] == 0.0 and got["LS"] == 32.0 and got["AOA"] == 308.4
    # the recommended settings name the hypotheses with an evidence dwell, as the table file does
    assert bank.estimator_settings["dwell_nats_per_hypothesis"] == {k: v for k, v in table.items() if v > 0.0}
    assert bank.FORMAT_VERSION == 4
    assert "dwell_nats_per_hypothesis" not in load_bank("untuned")[2].estimator_settings


def test_the_table_round_trips_and_moves_the_content_hash(tmp_path):
    plain = make_bank()
    table = make_bank(dwell_nats_per_hypothesis={"H1": 32.0, "H2": 0.5})
    assert plain.content_hash != table.content_hash
    path = tmp_path / "t.bank"
    table.save(path)
    back = core.load_bank(path)
    assert back.content_hash == table.content_hash
    assert {h.name: h.dwell_nats for h in back.hypotheses} == {"NONE": 0.0, "H1": 32.0, "H2": 0.5}
    assert back.estimator_settings["dwell_nats_per_hypothesis"] == {"H1": 32.0, "H2": 0.5}
    cleared = back.with_settings(dwell_nats_per_hypothesis={})
    assert cleared.content_hash == plain.content_hash   # no table: the bytes of a bank without one


def test_bad_tables_are_refused_naming_the_problem():
    with pytest.raises(ValueError, match="dwell_nats_per_hypothesis names 'XYZ', not a hypothesis of the bank"):
        make_bank(dwell_nats_per_hypothesis={"XYZ": 4.0})
    with pytest.raises(ValueError, match=r"'H1': N_k must be in \[0, 1e\+06\] nats, got -1"):
        make_bank(dwell_nats_per_hypothesis={"H1": -1.0})
    with pytest.raises(ValueError, match=r"dwell_nats must be in \[0, 1e\+06\] nats, got nan"):
        core.HypothesisModel(name="H", phi=[[0.5]], bd=[[1.0]], h=[[1.0]], k=[[0.5]], a=[[1.0]],
                             dwell_nats=float("nan"))
    base = {"name": "t", "estimator": {"dwell_nats_per_hypothesis": {"LS": -3}}}
    with pytest.raises(TuningError, match=r"dwell_nats_per_hypothesis: LS = -3 is outside \[0, 1e\+06\] nats"):
        tuning_from_dict(base)
    with pytest.raises(TuningError, match="dwell_nats_per_hypothesis must be a table NAME = nats"):
        tuning_from_dict({"name": "t", "estimator": {"dwell_nats_per_hypothesis": 32}})


def test_explicit_options_override_the_banks_table(tmp_path):
    bank = load_bank("tuned")[2]
    table = bank.estimator_settings["dwell_nats_per_hypothesis"]
    assert bank_estimator_settings(bank)["dwell_nats_per_hypothesis"] == table
    over = bank_estimator_settings(bank, {"dwell_nats": 48.0})   # one dwell for every hypothesis
    assert over["dwell_nats"] == 48.0 and "dwell_nats_per_hypothesis" not in over
    off = bank_estimator_settings(bank, {"dwell_nats": 0.0})     # the frame dwell alone
    assert "dwell_nats_per_hypothesis" not in off
    f = str(tmp_path / "n.txt")
    assert bank_estimator_settings(bank, {"dwell_nats_per_hypothesis": f})["dwell_nats_per_hypothesis"] == f


def _ready_line(args):
    return ready_line("--bank", load_bank("tuned")[1], *args)


def test_the_daemon_applies_the_banks_table_unless_a_flag_overrides_it():
    table = load_bank("tuned")[2].estimator_settings["dwell_nats_per_hypothesis"]
    listed = ", ".join(f"{k} {v:g}" for k, v in sorted(table.items()))
    assert f"dwell 0.25 s or per hypothesis ({listed}) nats," in _ready_line([])
    assert "per hypothesis" not in _ready_line(["--dwell-nats", "0"])
    assert "dwell 0.25 s or 48 nats," in _ready_line(["--dwell-nats", "48"])
    # a flight-phase dwell: the declarers' evidence dwell off (hierarchical_bank.h)
    assert "dwell 0.25 s, " in _ready_line(["--maneuver-dwell", "1"])
    assert "dwell 0.25 s, " in _ready_line(["--adapt-turbulence", "--adapt-reference-climb", "0.6",
                                            "--adapt-reference-climb-dwell", "1", "--dwell-nats", "48"])


@pytest.mark.slow
def test_daemon_executive_and_in_process_fly_the_banks_table_alike():
    """ROL fails at 1 s (N_k 32 nats in the shipped table): in lockstep over memq:// the
    daemon's executive declares what the in-process estimator declares, frame for frame; both
    declare ROL sooner than the frame dwell alone (--dwell-nats 0), so the table is in force."""
    from f16mmae.loop.flight import fly
    from test_hil_memq import _lockstep_equals_in_process

    bank = load_bank("tuned")[2]
    sc = Scenario(mach=0.4, alt_ft=20000.0, turbulence="light", duration_s=2.5, seed=2, feedback="mmae",
                  failures=(make_failure("ROL", 1.0),))
    remote, local = _lockstep_equals_in_process(bank, sc, "DN_")
    frame_dwell = fly(sc, bank, estimator_options={"dwell_nats": 0.0})
    assert remote.declarations[0]["hypothesis"] == "ROL" == frame_dwell.declarations[0]["hypothesis"]
    assert remote.declarations[0]["time_s"] < frame_dwell.declarations[0]["time_s"]
