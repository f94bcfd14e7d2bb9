"""mmae-daemon's flag table (cpp/daemon/daemon_config.cpp) and the harness's option table
(loop.estimator_options) agree on every flag the two share: a value the harness accepts the
daemon accepts, a value the harness refuses the daemon refuses, at both ends of each range and for
each choice, and each flag needs the same other flag. The daemon is asked through its parser
alone: a refused value exits 2 before any file is read; an accepted one goes on to the bank, which
does not exist (exit 1)."""
from __future__ import annotations

import math
import subprocess

import pytest

from f16mmae.loop.estimator_options import BY_KEY, ESTIMATOR_OPTIONS, EstimatorOption, check
from f16mmae.lcm.daemon import find_executable

DAEMON = str(find_executable("mmae-daemon"))
#: --actuator-limits is the harness's switch for the limits the daemon takes as values
#: (--actuator-rate-limits, --actuator-position-limits: test_daemon_config.cpp).
SHARED = [o for o in ESTIMATOR_OPTIONS if o.in_daemon and o.on_command_line and o.flag != "--actuator-limits"
          and o.kind in ("number", "choice", "switch")]
#: What the daemon needs besides the harness's requirement: the harness turns --adapt-own-channels
#: on, and gives --calm-complete and --calm-measure, for a scheduled bank by default
#: (estimator_options.scheduled_defaults), the daemon has no such default and
#: lcm.daemon.daemon_flags passes the flags.
DAEMON_ALSO_NEEDS = {"adapt_counted_channel": ["--adapt-own-channels"],
                     "calm_measure": ["--calm-complete", "VEL=1"],
                     "calm_whiteness_bound": ["--calm-complete", "VEL=1", "--calm-measure", "whiteness"]}


#: A valid entry of each table option another option needs.
TABLES = {"rough_dwell_s_per_hypothesis": "RUD=1"}


def _valid(o: EstimatorOption):
    """A value inside the option's range (not on its ends)."""
    if o.kind == "choice":
        return o.choices[0]
    upper = o.below if o.below is not None else o.maximum
    return (o.minimum + upper) / 2 if upper is not None else o.minimum + 1.0


def _with_requirements(o: EstimatorOption) -> tuple[list[str], dict]:
    """The daemon's arguments and the harness's settings of the options `o` needs, in force."""
    args, settings = [], {}
    r = o.requires
    while r is not None:
        need = BY_KEY[r]
        if need.kind == "switch":
            args, settings[need.key] = [need.flag, *args], True
        elif need.kind == "table":
            args, settings[need.key] = [need.flag, TABLES[need.key], *args], TABLES[need.key]
        else:
            args, settings[need.key] = [need.flag, str(_valid(need)), *args], _valid(need)
        r = need.requires
    return args, settings


def _daemon_accepts(args: list[str]) -> bool:
    p = subprocess.run([DAEMON, "--bank", "/nonexistent/bank.f16bank", "--lcm-url", "memq://", *args],
                       capture_output=True, text=True, timeout=20)
    assert p.returncode in (1, 2), (args, p.returncode, p.stdout + p.stderr)
    if p.returncode == 1:
        assert "bank.f16bank" in p.stdout + p.stderr, (args, p.stdout + p.stderr)
    return p.returncode == 1


def _harness_accepts(settings: dict) -> bool:
    try:
        check(settings)
    except ValueError:
        return False
    return True


def _probes(o: EstimatorOption) -> list:
    if o.kind == "switch":
        return [True]
    if o.kind == "choice":
        return [*o.choices, "bogus"]
    nudge = lambda x: 1e-6 * max(1.0, abs(x))  # noqa: E731
    values = [o.minimum, o.minimum - nudge(o.minimum), o.minimum + nudge(o.minimum), _valid(o)]
    for end in (o.below, o.maximum):
        if end is not None:
            values += [end, end - nudge(end), end + nudge(end)]
    return [v for v in values if math.isfinite(v)]


@pytest.mark.parametrize("option", SHARED, ids=[o.flag for o in SHARED])
def test_the_daemon_and_the_harness_take_the_same_values(option):
    needed_args, needed = _with_requirements(option)
    needed_args += DAEMON_ALSO_NEEDS.get(option.key, [])
    for value in _probes(option):
        args = [*needed_args, option.flag] + ([] if option.kind == "switch" else [repr(value) if isinstance(
            value, float) else value])
        harness = _harness_accepts({**needed, option.key: value})
        assert _daemon_accepts(args) == harness, (args, "harness accepts" if harness else "harness refuses")
    if option.requires is not None:  # without what it needs: refused by both
        value = True if option.kind == "switch" else _valid(option)
        args = [option.flag] + ([] if option.kind == "switch" else [str(value)])
        assert not _harness_accepts({option.key: value})
        assert not _daemon_accepts(args), args
