"""The per-flight table: columns, truth marking, and a lossless CSV round trip."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae.loop import timeseries as ts
from f16mmae.names import ACTUATORS, SENSORS


def synthetic(n=6):
    rng = np.random.default_rng(3)
    t = np.arange(n) / 64.0
    truth_log = {"state": rng.normal(size=(n, 2)), "state_names": ("alt_ft", "vt_fps"),
                 "surface_rad": rng.normal(size=(n, 5)),
                 "onsets": [{"name": "LS", "onset_s": 2 / 64.0}],
                 "failures": [{"name": "LS"}, {"name": "PIT"}]}
    probs = rng.uniform(size=(n, 2))
    probs[:2, 1] = np.nan  # off line at first
    return ts.flight_table(t, rng.normal(size=(n, 5)), rng.normal(size=(n, 7)), rng.normal(size=(n, 7)),
                           ("NONE", "LS"), probs, truth_log)


def test_columns_and_truth_marking():
    table = synthetic()
    names = list(table)
    assert names[:1 + 5] == ["time_s"] + [f"u_{a}_rad" for a in ACTUATORS]
    assert names[6:13] == [f"z_{s}" for s in SENSORS] and names[13:20] == [f"z_hat_{s}" for s in SENSORS]
    assert names[20:22] == ["p_NONE", "p_LS"]
    assert ts.truth_columns(names) == names[22:]
    assert "truth_state_alt_ft" in names and "truth_surface_RUD_rad" in names
    assert list(table["truth_failed_LS"]) == [0, 0, 1, 1, 1, 1]
    assert list(table["truth_failed_PIT"]) == [0] * 6  # injected, never acted in the flight


def test_csv_round_trip_is_exact(tmp_path):
    table = synthetic()
    path = ts.write_table(table, tmp_path / "flight", fmt="csv")
    assert path.name == "flight.csv"
    back = ts.read_table(path)
    assert list(back) == list(table)
    for k in table:
        np.testing.assert_array_equal(back[k], table[k])  # repr() keeps every bit; NaN stays NaN


def test_bad_shapes_and_format_are_named(tmp_path):
    t = np.arange(3) / 64.0
    log = {"state": np.zeros((3, 1)), "state_names": ("a",), "surface_rad": np.zeros((3, 5)),
           "onsets": [], "failures": []}
    with pytest.raises(ValueError, match=r"z has shape \(3, 6\)"):
        ts.flight_table(t, np.zeros((3, 5)), np.zeros((3, 6)), np.zeros((3, 7)), (), np.zeros((3, 0)), log)
    with pytest.raises(ValueError, match="valid: parquet, csv"):
        ts.write_table(synthetic(), tmp_path / "x", fmt="xlsx")


# -- a real flight: f16mmae run --out writes the table; u and z alone reproduce the estimator ------------
@pytest.mark.slow
def test_run_out_table_replays_from_u_and_z_alone(tmp_path):
    import ast
    import inspect

    from f16mmae.banks import load_bank
    from f16mmae.cli.main import main
    from f16mmae.loop import flight
    from f16mmae.loop.estimator import Estimator

    assert main(["run", "--fail", "LS@2.0", "--duration", "4", "--seed", "3", "--out", str(tmp_path)]) == 0
    path = next(tmp_path.glob("flight.*"))
    assert path.suffix == "." + ts.default_format()
    table = ts.read_table(path)
    n = len(table["time_s"])
    assert n == 4 * 64
    assert table["truth_failed_LS"][table["time_s"] < 2.0].max() == 0 and table["truth_failed_LS"][-1] == 1
    assert len(ts.truth_columns(list(table))) == 7 + 5 + 1  # states, surfaces, one failure
    # the estimator's outputs are a function of the u and z columns only
    est = Estimator(load_bank("tuned")[2])
    z_cols = [f"z_{s}" for s in SENSORS]
    u_cols = [f"u_{a}_rad" for a in ACTUATORS]
    for i in range(n):
        z_hat = est.update(np.array([table[c][i] for c in z_cols]))
        np.testing.assert_array_equal(z_hat, [table[f"z_hat_{s}"][i] for s in SENSORS])
        for h, p in zip(est.hypotheses, est.probabilities):
            assert table[f"p_{h}"][i] == p
        est.propagate(np.array([table[c][i] for c in u_cols]))
    # structurally: fly() reads the truth log only after its frame loop
    tree = ast.parse(inspect.getsource(flight.fly))
    loop = next(node for node in ast.walk(tree) if isinstance(node, ast.For))
    in_loop = {id(n) for n in ast.walk(loop)}
    reads = [n for n in ast.walk(tree) if isinstance(n, ast.Attribute) and n.attr == "truth_log"]
    assert reads and all(id(n) not in in_loop for n in reads)


def test_parquet_round_trip_marks_the_truth(tmp_path):
    import pyarrow.parquet as pq  # the test extra installs it; without it run --out writes CSV

    table = synthetic()
    path = ts.write_table(table, tmp_path / "flight", fmt="parquet")
    assert path.suffix == ".parquet"
    assert pq.read_schema(path).metadata[b"f16mmae.truth_prefix"] == ts.TRUTH_PREFIX.encode()
    back = ts.read_table(path)
    for k in table:
        np.testing.assert_array_equal(back[k], table[k])
