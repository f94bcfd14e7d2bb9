"""What `pip install .` gives a user: `mmae-daemon` on PATH (the wheel's scripts directory),
`mmae-daemon --bank ...` runnable as the README and `f16mmae hil --help` say, and none of the
latency tools (tools/latency: echo, idle-jitter, the LCM latency driver) in the wheel. The wheel is built from the build tree `make build`
keeps (build/py: nothing is compiled again) and installed, without its Python dependencies
(the daemon needs none), into a fresh virtual environment."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_a_fresh_venv_has_mmae_daemon_on_path_and_no_latency_tools(tmp_path):
    wheels = tmp_path / "wheels"
    subprocess.run(["flock", str(ROOT / "build" / ".lock"), sys.executable, "-m", "pip", "wheel", "-q", "--no-deps",
                    "--no-build-isolation", f"-Cbuild-dir={ROOT / 'build' / 'py'}", "-w", str(wheels), str(ROOT)],
                   check=True, timeout=900, capture_output=True)
    (wheel,) = wheels.glob("f16mmae-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert any(n.endswith(".data/scripts/mmae-daemon") for n in names), names
    assert not [n for n in names if any(t in n for t in ("lcm-echo-f16", "idle-jitter", "cpu_work", "lcm_latency"))]

    env_dir = tmp_path / "fresh"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    bin_dir = env_dir / "bin"
    subprocess.run([str(bin_dir / "python"), "-m", "pip", "install", "-q", "--no-deps", "--no-index", str(wheel)],
                   check=True, timeout=300, capture_output=True)
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}/usr/bin:/bin"}
    env.pop("F16MMAE_BIN_DIR", None)
    p = subprocess.run(["mmae-daemon", "--help"], env=env, capture_output=True, text=True, timeout=30)
    assert p.returncode == 0 and "mmae-daemon --bank FILE" in p.stdout, p.stdout + p.stderr
    bank = ROOT / "python" / "harness" / "f16mmae" / "data" / "nominal_tuned.f16bank"
    d = subprocess.Popen(["mmae-daemon", "--bank", str(bank), "--lcm-url", "memq://"], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    ready = d.stdout.readline()
    d.send_signal(signal.SIGINT)
    out, err = d.communicate(timeout=10)
    assert "mmae-daemon: ready: bank" in ready and d.returncode == 0, ready + out + err
