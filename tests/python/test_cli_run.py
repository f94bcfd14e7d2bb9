"""Command-line handling of run / campaign / report: clear errors naming the bad value."""
from __future__ import annotations

import pytest

from f16mmae.cli.main import main


@pytest.mark.parametrize(
    "argv, expected",
    [
        (["run", "--turbulence", "heavy"], "'heavy' is unknown; valid: none, light, moderate, severe"),
        (["run", "--feedback", "kalman"], "'kalman' is unknown; valid: mmae, raw"),
        (["run", "--seed", "0"], "--seed '0' must be >= 1"),
        (["run", "--seed", "x"], "--seed 'x' is not an integer"),
        (["run", "--duration", "-2"], "--duration '-2' must be > 0"),
        (["run", "--bank", "/no/such.f16bank"], "neither a shipped tuning (tuned, untuned), nor 'scheduled', nor 'turbulence', nor a readable bank file"),
        (["run", "--fail", "FOO@3.0"], "FOO"),
        (["run", "--fail", "LS@9.0"], "not inside the 8.0-s flight"),
        (["run", "--mach", "0.9"], "--mach '0.9' must be <= 0.8 (valid: [0.3, 0.8])"),
        (["run", "--dwell-s", "-1"], "--dwell-s -1.0 must lie in [0, 60]"),
        (["run", "--fail", "PIT@1:sideways"], "unknown failure mode 'sideways' for sensor PIT; valid:"),
        (["campaign", "single", "--dither-scale", "9"], "--dither-scale '9' must be <= 5.0 (valid: [0.0, 5.0])"),
        (["campaign", "single", "--threshold", "0.3"], "--threshold 0.3 must lie in (0.5, 1)"),
        (["campaign", "single", "--cases", "LS,XX"], "unknown case(s) XX; valid: NONE,LS,RS"),
        (["campaign", "single", "--runs", "0"], "--runs '0' must be >= 1"),
        (["campaign", "single", "--turbulence", "gusty"], "'gusty' is unknown"),
        (["campaign", "single", "--workers", "0"], "--workers '0' must be >= 1"),
        (["campaign", "single", "--workers", "2", "--scheduler", "tcp://h:1"], "not both"),
        (["campaign", "single", "--scheduler", "h:1", "--out", "{tmp}"], "tcp://HOST:PORT"),
        (["campaign", "single", "--tuning", "wobbly"], "--tuning 'wobbly' is neither tuned, untuned"),
        (["report", "{tmp}"], "neither summary.json"),
    ],
)
def test_bad_arguments_exit_2_with_a_clear_message(argv, expected, capsys, tmp_path):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert expected in err, err
    assert "Traceback" not in err


def test_help_teaches_with_examples(capsys):
    for argv in (["run", "--help"], ["campaign", "single", "--help"], ["report", "--help"]):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 0
        assert "examples:" in capsys.readouterr().out
