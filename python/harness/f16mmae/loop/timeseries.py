"""One table per flight: what the estimator saw and said, and, marked apart, the truth.

Row ``i`` is frame ``i`` at ``t_i = i / FRAME_RATE_HZ`` (the closed loop's order: ``z_i``
measured, ``z_hat_i = estimator.update(z_i)``, ``u_i`` commanded).  Columns, in order:

* ``time_s``;
* ``u_<LS..RUD>_rad`` -- the surface commands ``u_i`` the estimator propagated (and
  ``u_THR`` -- the throttle command, with a bank that models the throttle);
* ``z_<VEL..AY>`` -- the measurements ``z_i`` it was given (units of ``names.SENSOR_UNITS``);
* ``z_hat_<VEL..AY>`` -- its blended estimate after the update;
* ``p_<hypothesis>`` -- the probabilities, one column per hypothesis that was on line during
  the flight (NaN while off line);
* ``truth_state_<name>`` -- the truth model's state at ``t_i`` (``truth.model.STATE_LOG``);
* ``truth_surface_<LS..RUD>_rad`` -- the effective surface positions at the end of frame ``i``;
* ``truth_failed_<NAME>`` -- 1 from the frame at whose time the injected failure had acted
  (its recorded onset), else 0.

Every column whose name starts with :data:`TRUTH_PREFIX` is truth: it is recorded after the
fact from the truth model and never reaches the estimator.  Written as Parquet (the schema's
metadata names the truth prefix) when ``pyarrow`` is installed, else as CSV.
"""
from __future__ import annotations

import csv
import importlib.util
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..names import ACTUATORS, INPUTS_WITH_THROTTLE, SENSORS

TRUTH_PREFIX = "truth_"
FORMATS: tuple[str, ...] = ("parquet", "csv")


def default_format() -> str:
    """``parquet`` when pyarrow is importable, else ``csv``."""
    return "parquet" if importlib.util.find_spec("pyarrow") is not None else "csv"


def flight_table(time_s, u, z, z_hat, hypotheses: Sequence[str], probabilities, truth_log: dict) -> dict:
    """The table (column name -> 1-D array, in column order) of one flight; see the module
    docstring.  ``u``, ``z``, ``z_hat``: (n, 5) or (n, 6) with the throttle, (n, 7), (n, 7); ``probabilities``:
    (n, len(hypotheses)); ``truth_log``: ``TruthModel.truth_log`` of the same flight."""
    t = np.asarray(time_s, dtype=float)
    n = len(t)
    u = np.asarray(u, float)
    inputs = INPUTS_WITH_THROTTLE if u.ndim == 2 and u.shape[1] == len(INPUTS_WITH_THROTTLE) else ACTUATORS
    arrays = {"u": (u, inputs), "z": (np.asarray(z, float), SENSORS),
              "z_hat": (np.asarray(z_hat, float), SENSORS)}
    for what, (a, names) in arrays.items():
        if a.shape != (n, len(names)):
            raise ValueError(f"{what} has shape {a.shape}, the table needs ({n}, {len(names)})")
    p = np.asarray(probabilities, float).reshape(n, -1)
    if p.shape[1] != len(hypotheses):
        raise ValueError(f"probabilities have {p.shape[1]} columns for {len(hypotheses)} hypotheses")
    cols: dict[str, np.ndarray] = {"time_s": t}
    cols.update({f"u_{a}_rad" if a in ACTUATORS else f"u_{a}": u[:, k] for k, a in enumerate(inputs)})
    cols.update({f"z_{s}": arrays["z"][0][:, k] for k, s in enumerate(SENSORS)})
    cols.update({f"z_hat_{s}": arrays["z_hat"][0][:, k] for k, s in enumerate(SENSORS)})
    cols.update({f"p_{h}": p[:, k] for k, h in enumerate(hypotheses)})
    state = np.asarray(truth_log["state"], float)[:n]
    surface = np.asarray(truth_log["surface_rad"], float)[:n]
    if len(state) != n or len(surface) != n:
        raise ValueError(f"the truth log holds {len(state)} states and {len(surface)} surface rows "
                         f"for {n} frames")
    cols.update({f"{TRUTH_PREFIX}state_{name}": state[:, k] for k, name in enumerate(truth_log["state_names"])})
    cols.update({f"{TRUTH_PREFIX}surface_{a}_rad": surface[:, k] for k, a in enumerate(ACTUATORS)})
    for onset in truth_log["onsets"]:
        cols[f"{TRUTH_PREFIX}failed_{onset['name']}"] = (t >= onset["onset_s"] - 1e-9).astype(float)
    for f in truth_log["failures"]:  # a failure that never acted within the flight
        cols.setdefault(f"{TRUTH_PREFIX}failed_{f['name']}", np.zeros(n))
    return cols


def truth_columns(columns: Sequence[str]) -> list[str]:
    """The names among ``columns`` that hold truth."""
    return [c for c in columns if c.startswith(TRUTH_PREFIX)]


def write_table(table: dict, path_stem: str | Path, fmt: str | None = None) -> Path:
    """Write ``table`` to ``path_stem`` + ``.parquet`` or ``.csv`` (``fmt``, default
    :func:`default_format`); returns the path written."""
    fmt = fmt or default_format()
    if fmt not in FORMATS:
        raise ValueError(f"unknown table format {fmt!r}; valid: {', '.join(FORMATS)}")
    stem = Path(path_stem)
    if fmt == "parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        path = stem.with_suffix(".parquet")
        schema_meta = {b"f16mmae.truth_prefix": TRUTH_PREFIX.encode()}
        pq.write_table(pa.table({k: np.asarray(v) for k, v in table.items()}).replace_schema_metadata(schema_meta),
                       path)
        return path
    path = stem.with_suffix(".csv")
    names = list(table)
    data = np.column_stack([np.asarray(table[k], float) for k in names])
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names)
        for row in data:
            w.writerow(["" if np.isnan(x) else repr(float(x)) for x in row])
    return path


def read_table(path: str | Path) -> dict:
    """A table written by :func:`write_table` (column name -> float array; NaN for empty cells)."""
    path = Path(path)
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        t = pq.read_table(path)
        return {name: t.column(name).to_numpy().astype(float) for name in t.column_names}
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty table")
    names, body = rows[0], rows[1:]
    data = np.array([[float(x) if x else np.nan for x in r] for r in body], dtype=float).reshape(len(body), len(names))
    return {name: data[:, k] for k, name in enumerate(names)}
