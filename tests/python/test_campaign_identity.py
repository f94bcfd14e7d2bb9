"""Code identity: git commit and dirty flag, or a source hash without git."""
from __future__ import annotations

import shutil
import subprocess

import pytest

from f16mmae.campaign.engine import identity


def git(cwd, *args):
    return subprocess.run(("git", *args), cwd=cwd, check=True, capture_output=True, text=True).stdout


@pytest.fixture
def repo(tmp_path):
    if shutil.which("git") is None:
        pytest.fail("git is needed for the identity tests")
    git(tmp_path, "init", "-q")
    git(tmp_path, "config", "user.email", "t@example.com")
    git(tmp_path, "config", "user.name", "t")
    (tmp_path / "a.py").write_text("x = 1\n")
    git(tmp_path, "add", "a.py")
    git(tmp_path, "commit", "-q", "-m", "one")
    return tmp_path


def test_git_identity_names_the_commit_and_uncommitted_states(repo):
    head = git(repo, "rev-parse", "HEAD").strip()
    assert identity.git_identity(repo) == f"git:{head}"
    (repo / "a.py").write_text("x = 2\n")
    dirty1 = identity.git_identity(repo)
    assert dirty1.startswith(f"git:{head}+dirty.")
    (repo / "a.py").write_text("x = 3\n")
    dirty2 = identity.git_identity(repo)
    assert dirty2.startswith(f"git:{head}+dirty.") and dirty2 != dirty1
    (repo / "a.py").write_text("x = 1\n")
    (repo / "new.py").write_text("y = 1\n")  # an untracked source counts
    assert identity.git_identity(repo).startswith(f"git:{head}+dirty.")


def test_source_identity_without_git(tmp_path):
    (tmp_path / "m.py").write_text("a = 1\n")
    (tmp_path / "core.so").write_bytes(b"\x7fELF")
    assert identity.git_identity(tmp_path) is None
    one = identity.source_identity(tmp_path)
    assert one.startswith("src:") and one == identity.source_identity(tmp_path)
    (tmp_path / "core.so").write_bytes(b"\x7fELF2")
    assert identity.source_identity(tmp_path) != one
    (tmp_path / "notes.txt").write_text("not code")
    (tmp_path / "core.so").write_bytes(b"\x7fELF")
    assert identity.source_identity(tmp_path) == one


def test_running_code_identity_and_versions():
    import jsbsim

    ident = identity.code_identity()
    assert ident["jsbsim"] == jsbsim.__version__ or ident["jsbsim"].startswith(jsbsim.__version__.split("+")[0])
    assert ident["lcm"] is not None
    assert ident["code"].startswith(("git:", "src:"))
    assert identity.same(ident, dict(ident))
    assert not identity.same(ident, {**ident, "jsbsim": "0.0"}) and not identity.same(ident, None)
    assert "unrecorded" in identity.describe(None)
    assert ident["code"] in identity.describe(ident)


# -- a resumed campaign refuses runs of other code -------------------------------------------------------
@pytest.mark.slow
def test_resume_over_other_code_refuses_unless_allowed(tmp_path, capsys):
    import json

    from f16mmae.campaign.engine.config import CampaignError
    from f16mmae.campaign.engine.executor import InlineExecutor
    from f16mmae.campaign.single import SingleCampaign, run_campaign
    from f16mmae.cli.main import main

    def fly(runs, **kw):
        return run_campaign(SingleCampaign(runs=runs, cases=("NONE",), baseline=None), tmp_path, InlineExecutor(),
                            show_progress=False, measure_cost=False, **kw)

    fly(1)
    path = tmp_path / "runs.jsonl"
    record = json.loads(path.read_text())
    ours = record["code"]
    assert ours == identity.code_identity()
    other = {**ours, "code": "git:0123456789abcdef0123456789abcdef01234567"}
    path.write_text(json.dumps({**record, "code": other}) + "\n")
    with pytest.raises(CampaignError) as err:
        fly(2)
    msg = str(err.value)
    assert identity.describe(other) in msg and identity.describe(ours) in msg
    assert "--allow-mixed" in msg and "--out" in msg
    assert path.read_text().count("\n") == 1  # nothing flown, nothing lost
    # the command line says the same and exits non-zero
    argv = ["campaign", "single", "--runs", "2", "--cases", "NONE", "--baseline", "none", "--workers", "1",
            "--out", str(tmp_path), "--quiet"]
    assert main(argv) != 0
    assert "resuming would mix results of different code" in capsys.readouterr().err
    # allowed: the stored run is kept, the new one flown with this code, the summary says so
    done = fly(2, allow_mixed=True)
    assert done.executed == 1 and done.resumed == 1
    assert sorted(done.summary["codes_in_records"].values()) == [1, 1]
    # a record from before identities were kept is refused too
    lines = path.read_text().splitlines()
    old = json.loads(lines[0])
    old.pop("code")
    path.write_text(json.dumps(old) + "\n" + lines[1] + "\n")
    with pytest.raises(CampaignError, match="unrecorded"):
        fly(2)
