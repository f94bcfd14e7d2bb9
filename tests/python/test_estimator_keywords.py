"""The estimator's keyword table (bindings/estimator_init.h): every keyword a row, each row's
documented default the core's own, and errors that name the keyword."""
from __future__ import annotations

import ast
import re

import numpy as np
import pytest

from f16mmae import core
from f16mmae.design import bank as design_bank

CLASSES = (core.HierarchicalBank, core.Executive, core.TurbulenceBankSet)


@pytest.fixture(scope="module")
def tuned():
    return core.load_bank(design_bank.nominal_bank_path("tuned"))


def _documented(cls) -> dict[str, object]:
    """The keywords and their defaults, as the constructor's docstring writes them."""
    rows = re.findall(r"^  (\w+): .+ = (.+)$", cls.__init__.__doc__, flags=re.M)
    return {name: ast.literal_eval(value) for name, value in rows}


def test_every_class_takes_the_same_keywords():
    tables = [_documented(cls) for cls in CLASSES]
    assert len(tables[0]) > 50
    assert all(t == tables[0] for t in tables[1:])


def _fly(bank, **keywords) -> tuple[np.ndarray, list]:
    """300 frames at trim with seeded noise and a rudder doublet: probabilities and declarations."""
    est = core.HierarchicalBank(bank, **keywords)
    rng = np.random.default_rng(3)
    u0, z0 = np.asarray(bank.u_trim), np.asarray(bank.z_trim)
    out = []
    for i in range(300):
        u = u0.copy()
        u[-1] += 0.02 * np.sign(np.sin(2 * np.pi * i / 64.0))
        est.step(z0 + 0.002 * rng.standard_normal(z0.size), u)
        out.append(est.probabilities.copy())
    return np.array(out), est.declarations


def test_the_documented_defaults_are_the_core_defaults(tuned):
    """Each row's default, given explicitly, flies the bank exactly as no keyword at all: a row
    that set another field, or documented another value, would change the flight."""
    defaults = _documented(core.HierarchicalBank)
    p0, d0 = _fly(tuned)
    p1, d1 = _fly(tuned, **defaults)
    assert np.array_equal(p0, p1, equal_nan=True) and d0 == d1


def test_a_keyword_changes_the_flight(tuned):
    """The table's rows reach the core: a floor ten times higher moves the probabilities."""
    p0, _ = _fly(tuned)
    p1, _ = _fly(tuned, p_min=0.01)
    assert not np.array_equal(p0, p1)
    assert p1.min() >= 0.01 * 0.999


@pytest.mark.parametrize("keywords, error, message", [
    ({"p_mim": 0.01}, TypeError, "unexpected estimator keyword argument 'p_mim'"),
    ({"p_min": "0.01"}, TypeError, "p_min must be a number, got str"),
    ({"adapt_turbulence": "yes"}, TypeError, "adapt_turbulence must be True or False, got str"),
    ({"trim_steady_measurements": 3}, TypeError, "trim_steady_measurements must be a list of strings, got int"),
    ({"maneuver_trim_rates": "gps"}, ValueError, "maneuver_trim_rates must be 'air' or 'inertial', got 'gps'"),
    ({"declarer": 0.9}, ValueError, "declarer must be a core.Declarer"),
])
def test_bad_keywords_are_named(tuned, keywords, error, message):
    with pytest.raises(error, match=re.escape(message)):
        core.HierarchicalBank(tuned, **keywords)


def test_the_declarer_supplies_the_rule_whatever_the_order(tuned):
    """A core.Declarer given with threshold and dwell_s: its own values are in force, before or
    after them in the call."""
    declarer = core.Declarer(threshold=0.99, dwell_s=0.5)
    a, da = _fly(tuned, declarer=declarer, threshold=0.5, dwell_s=0.0)
    b, db = _fly(tuned, threshold=0.5, dwell_s=0.0, declarer=declarer)
    c, dc = _fly(tuned, threshold=0.99, dwell_s=0.5)
    assert np.array_equal(a, c) and np.array_equal(b, c) and da == db == dc
