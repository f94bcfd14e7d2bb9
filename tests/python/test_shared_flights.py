"""engine.shared_flights: a record is reused only within the context, for the same run function
and an equal spec; a run function's ``shares`` declares the record of its base function."""
from __future__ import annotations

from f16mmae.campaign.engine import shared_flights


def base(spec: dict) -> dict:
    return {"run_key": spec["run_key"], "value": spec["x"] * 2}


def labelled(spec: dict) -> dict:
    return {**base(spec), "point": spec["point"]}


labelled.shares = (base, ("point",))


def other(spec: dict) -> dict:
    return base(spec)


SPEC = {"run_key": "k1", "x": 21, "bank": "tuned"}


def test_nothing_is_kept_outside_the_context():
    shared_flights.offer(base, SPEC, base(SPEC))
    assert shared_flights.take(base, SPEC) is None


def test_the_same_function_and_an_equal_spec_take_the_record():
    with shared_flights.sharing():
        shared_flights.offer(base, SPEC, base(SPEC))
        assert shared_flights.take(base, dict(SPEC)) == {"run_key": "k1", "value": 42}
        assert shared_flights.take(other, SPEC) is None                      # another function
        assert shared_flights.take(base, {**SPEC, "bank": "file.bank"}) is None  # same key, other field
        assert shared_flights.take(base, {**SPEC, "run_key": "k2"}) is None
    assert shared_flights.take(base, SPEC) is None  # gone with the context


def test_a_labelled_record_is_the_base_functions_without_its_tags():
    spec = {**SPEC, "point": "NOM"}
    with shared_flights.sharing():
        shared_flights.offer(labelled, spec, labelled(spec))
        assert shared_flights.take(base, SPEC) == base(SPEC)
        assert shared_flights.take(labelled, spec) == labelled(spec)
        assert shared_flights.take(base, {**SPEC, "x": 1}) is None
