"""The shipped ``tuned`` tuning is reproducible: re-running the documented two-stage
calibration (design/calibrate.py, convergence.py: measurements against the nonlinear truth)
gives the same file; stage 1 makes the NONE filter consistent, stage 2 improves the bank's
probability convergence."""
from __future__ import annotations

import numpy as np
import pytest

from f16mmae import names
from f16mmae.design import calibrate
from f16mmae.design.tuning import TUNINGS_DIR


def test_tuned_toml_is_what_the_calibration_produces():
    tun, hist, conv = calibrate.run_calibration()
    text = calibrate.render_toml(tun, hist[0], hist[-2], hist[-1], conv)
    assert text == (TUNINGS_DIR / "tuned.toml").read_text(), (
        "tunings/tuned.toml is stale (the truth model changed?): run "
        "'python -m f16mmae.design.calibrate --write'")
    untuned, stage1 = hist[0], hist[-2]
    assert untuned.nis_mean > 2 * names.NZ  # the untuned design is clearly mismatched
    assert abs(stage1.nis_mean - names.NZ) < 0.1 * names.NZ
    assert np.all(stage1.var_over_a < 1.15) and np.all(stage1.var_over_a > 0.5)
    kept = [r for r in conv if r["kept"]]
    assert kept[-1]["J"] >= kept[0]["J"]


def test_failure_log_odds_peak_with_no_tempering_is_the_plain_filter_bank_s():
    """At a reference no light-turbulence power ratio reaches (s stays at its floor 1), the
    estimator's peak failure log-odds over the calibration flights is that of an independent
    replay: the 13 level-0 filters of the bank as one core.FilterBank (perturbation signals,
    the bank's p_min), max over frames of max_k ln p_k - ln p_NONE."""
    from f16mmae import core
    from f16mmae.banks import load_bank

    bank = load_bank("tuned")[2]
    flights = calibrate.node_flights(0.4, 20_000.0, "light")[:3]
    models = [core.FilterModel(phi=h.phi, bd=h.bd, h=h.h, k=h.k, a=h.a)
              for h in (bank[name] for name in names.SINGLE_HYPOTHESES)]
    plain = core.FilterBank(models, p_min=bank.p_min)
    peak = -np.inf
    for fl in flights:
        plain.reset()
        for z, u in zip(fl.z, fl.u):
            p = plain.step(z, u)
            peak = max(peak, float(np.log(p[1:].max()) - np.log(p[0])))
    assert calibrate.failure_log_odds_peak(bank, flights, 50.0) == pytest.approx(peak, abs=1e-9)


def test_the_calibration_flies_the_estimator_s_start_up():
    """A start-up as long as the flights weighs no hypothesis in any frame: the peak failure
    log-odds is where the estimator starts, ln(p_min / (1 - 12 p_min)) (about -20.72 at 1e-9),
    while the same flights without it climb above; bounded_reference passes it on (every
    reference then keeps the start)."""
    from f16mmae.banks import load_bank

    bank = load_bank("tuned")[2]
    flights = calibrate.node_flights(0.4, 20_000.0, "light")[:2]
    start = float(np.log(bank.p_min / (1.0 - 12 * bank.p_min)))
    assert start == pytest.approx(-20.7232658, abs=1e-6)
    assert calibrate.failure_log_odds_peak(bank, flights, 0.6, start_up_s=8.0) == pytest.approx(start, abs=1e-9)
    assert calibrate.failure_log_odds_peak(bank, flights, 0.6) > start + 5.0
    assert calibrate.bounded_reference(bank, flights, start + 1e-6, (0.4, 1.0), 0.1, start_up_s=8.0) == (
        1.0, pytest.approx(start, abs=1e-9))


def test_bounded_reference_is_the_largest_grid_reference_within_the_bound():
    """The bisection finds what a scan of the grid finds: the largest reference at and below
    which every reference keeps the peak within the bound (lower references temper more, so
    the peak falls with them); a bound nothing meets gives the grid's lower end."""
    from f16mmae.banks import load_bank

    bank = load_bank("tuned")[2]
    flights = calibrate.node_flights(0.4, 20_000.0, "light")[:4]
    grid = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
    peaks = [calibrate.failure_log_odds_peak(bank, flights, r) for r in grid]
    assert peaks[0] < peaks[-1]
    bound = (peaks[2] + peaks[3]) / 2.0
    expected = max(n for n in range(len(grid)) if all(p <= bound for p in peaks[:n + 1]))
    ref, peak = calibrate.bounded_reference(bank, flights, bound, (0.4, 1.0), 0.1)
    assert ref == pytest.approx(grid[expected]) and peak == pytest.approx(peaks[expected])
    assert calibrate.bounded_reference(bank, flights, -100.0, (0.4, 1.0), 0.1) == (0.4, pytest.approx(peaks[0]))


def test_declaration_effort_is_the_climb_from_the_floor_times_the_scale():
    """By hand: p_min 1e-3, 13 hypotheses, threshold 0.9, s = 2:
    2 (ln 9 - ln(0.001 / 0.988)) = 2 (2.1972246 + 6.8956827) = 18.1858146."""
    assert calibrate.declaration_effort(1e-3, 0.9, 2.0) == pytest.approx(18.1858146, abs=1e-6)
    assert calibrate.declaration_effort(1e-9, 0.9, 1.0) == pytest.approx(2.1972246 + 20.7232658, abs=1e-6)


def test_the_log_odds_bound_is_the_same_share_of_the_climb_at_every_floor():
    """-6 at 1e-9 (the bound as chosen); by hand at 1e-3 with threshold 0.9 and 13 hypotheses:
    floor ln(0.001 / 0.988) = -6.8956827, climb 2.1972246 + 6.8956827 = 9.0929073, share
    (-6 + 20.7232658) / (2.1972246 + 20.7232658) = 0.6423627 -> -6.8956827 + 5.8409436 = -1.0547391."""
    assert calibrate.log_odds_bound(1e-9, 0.9) == pytest.approx(-6.0, abs=1e-12)
    assert calibrate.log_odds_bound(1e-3, 0.9) == pytest.approx(-1.0547391, abs=2e-6)


def test_bounded_settings_takes_the_least_effort_floor_among_those_within_the_bound():
    """Each candidate floor's row is that floor's bounded reference (bounded_reference on the
    bank recommending it) with the scale the estimator holds there; the chosen row met the
    bound and no other row that met it needs less effort; a bound nothing meets gives the
    smallest floor."""
    from f16mmae.banks import load_bank

    bank = load_bank("tuned")[2]
    flights = calibrate.node_flights(0.4, 20_000.0, "light")[:3]
    chosen = calibrate.bounded_settings(bank, flights, (1e-9, 1e-3))
    rows = {p: (ref, peak, s, met) for p, ref, peak, s, met in chosen["candidates"]}
    assert sorted(rows) == [1e-9, 1e-3]
    for p, (ref, peak, s, met) in rows.items():
        limit = calibrate.log_odds_bound(p, bank.threshold)
        expected = calibrate.bounded_reference(bank.with_settings(p_min=p), flights, limit)
        assert ref == expected[0] and peak == round(expected[1], 2) and s >= 1.0 and met == (expected[1] <= limit)
    assert chosen["bound_met"] and chosen["failure_log_odds_peak"] <= calibrate.log_odds_bound(chosen["p_min"], 0.9)
    assert rows[chosen["p_min"]][0] == chosen["adapt_reference"]
    met = [p for p, row in rows.items() if row[3]]
    efforts = {p: calibrate.declaration_effort(p, bank.threshold, rows[p][2]) for p in met}
    assert chosen["effort"] == pytest.approx(min(efforts.values()), abs=0.01)
    none = calibrate.bounded_settings(bank, flights, (1e-9, 1e-3), bound=-100.0)
    assert not none["bound_met"] and none["p_min"] == 1e-9


def test_the_calm_air_reference_lies_between_the_measured_power_ratios_of_calm_and_light_air():
    """calibrate.calm_reference: the measured power ratio rho-bar of the scheduled estimator's
    count (own channels, VEL counted) averaged over the flights after their first second, in calm
    air and in light turbulence, and their midpoint: light air reads higher than calm air at the
    nominal point, by more than the flights' spread."""
    from f16mmae.banks import load_bank

    bank = load_bank("tuned")[2]
    calm = calibrate.node_flights(0.4, 20_000.0, "none")[:2]
    light = calibrate.node_flights(0.4, 20_000.0, "light")[:2]
    reference, r_calm, r_light = calibrate.calm_reference(bank, calm, light)
    assert r_calm < reference < r_light
    assert reference == round(0.5 * (r_calm + r_light), 3)
    each = [calibrate.measured_power_ratio(bank, [f]) for f in calm + light]
    assert max(each[:2]) < min(each[2:])
