"""A campaign owns its directory while it runs, and its pool workers die with it (issue 16,
item 6): a second campaign on the same ``--out`` is refused with a sentence; after a
``kill -9`` of a campaign its workers are gone within seconds and the same command resumes."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from f16mmae.campaign.engine.store import LOCK_FILE, StoreError, campaign_directory
from f16mmae.cli.main import main

HOLD = """
import sys, time
from f16mmae.campaign.engine.store import campaign_directory
with campaign_directory(sys.argv[1]):
    print("locked", flush=True)
    time.sleep(60)
"""


def _hold_lock(directory: Path) -> subprocess.Popen:
    proc = subprocess.Popen([sys.executable, "-c", HOLD, str(directory)], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "locked"
    return proc


def _alive_children(pid: int) -> list[int]:
    """Processes whose parent is ``pid`` and that are not zombies."""
    out = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[1].split()
        if int(fields[1]) == pid and fields[0] != "Z":
            out.append(int(entry.name))
    return out


def _alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def test_a_second_campaign_on_a_locked_directory_is_refused(tmp_path, capsys):
    holder = _hold_lock(tmp_path)
    try:
        with pytest.raises(StoreError, match=f"another campaign \\(pid {holder.pid}\\) is writing to {tmp_path}"):
            with campaign_directory(tmp_path):
                pass
        argv = ["campaign", "single", "--runs", "1", "--cases", "NONE", "--baseline", "none", "--workers", "1",
                "--quiet", "--out", str(tmp_path)]
        assert main(argv) == 2
        captured = capsys.readouterr()
        assert f"another campaign (pid {holder.pid}) is writing to {tmp_path}" in captured.err
        assert not (tmp_path / "runs.jsonl").exists()  # nothing flown, nothing written twice
    finally:
        holder.kill()
        holder.wait()
        holder.stdout.close()
    with campaign_directory(tmp_path) as d:  # the kernel dropped the dead holder's lock
        assert (d / LOCK_FILE).read_text().strip() == str(os.getpid())


@pytest.mark.slow
def test_kill_9_of_a_campaign_takes_its_workers_along_and_the_campaign_resumes(tmp_path):
    argv = [sys.executable, "-m", "f16mmae", "campaign", "single", "--runs", "6", "--cases", "NONE,LS",
            "--baseline", "none", "--workers", "2", "--quiet", "--out", str(tmp_path)]
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    workers: list[int] = []
    try:
        deadline = time.monotonic() + 60
        while len(workers) < 2 and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.05)
            workers = _alive_children(proc.pid)
        assert len(workers) >= 2, "the campaign did not start its two workers"
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        deadline = time.monotonic() + 5
        while any(_alive(w) for w in workers) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not [w for w in workers if _alive(w)], "pool workers outlived their campaign"
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for w in workers:  # a failed check leaves no orphan behind
            if _alive(w):
                os.kill(w, signal.SIGKILL)
    # the lock died with the campaign: the same command resumes and completes
    assert main(argv[3:-5] + ["--workers", "1", "--quiet", "--out", str(tmp_path)]) == 0
    assert len((tmp_path / "runs.jsonl").read_text().splitlines()) == 12
