"""Code identity: which code produced a record, so runs of different code are never mixed.

``code_identity()`` returns ``{"code": ..., "jsbsim": ..., "lcm": ...}``:

* ``code`` -- ``git:<commit>`` when the package is imported from a git checkout, with
  ``+dirty.<h>`` appended when tracked or untracked (not ignored) files differ from the
  commit, ``h`` the first 12 hex digits of the SHA-256 of ``git diff HEAD`` plus the
  untracked files' names and contents (two different uncommitted states differ);
  otherwise ``src:<h>``, ``h`` the SHA-256 of the package's Python sources and its built
  extension (relative path and bytes of each file, in sorted order).
* ``jsbsim`` / ``lcm`` -- the installed distributions' versions (``None`` if absent).

The result is computed once per process.  :func:`describe` gives it as one line for
messages, :func:`same` compares two identities.
"""
from __future__ import annotations

import functools
import hashlib
import subprocess
from importlib import metadata
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parents[2]  # .../f16mmae
IDENTITY_FIELDS: tuple[str, ...] = ("code", "jsbsim", "lcm")


def _git(*args: str, cwd: Path) -> bytes | None:
    try:
        res = subprocess.run(("git", *args), cwd=cwd, capture_output=True, timeout=30, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return res.stdout if res.returncode == 0 else None


def git_identity(directory: Path = PACKAGE_DIR) -> str | None:
    """``git:<commit>[+dirty.<h>]`` of the checkout holding ``directory``, None outside git."""
    top = _git("rev-parse", "--show-toplevel", cwd=directory)
    head = _git("rev-parse", "HEAD", cwd=directory)
    if top is None or head is None:
        return None
    root = Path(top.decode().strip())
    status = _git("status", "--porcelain", cwd=root)
    if status is None:
        return None
    ident = f"git:{head.decode().strip()}"
    if status.strip():
        h = hashlib.sha256(_git("diff", "HEAD", "--binary", cwd=root) or b"")
        untracked = _git("ls-files", "--others", "--exclude-standard", "-z", cwd=root) or b""
        for name in sorted(n for n in untracked.split(b"\0") if n):
            path = root / name.decode()
            h.update(name + b"\0")
            if path.is_file():
                h.update(path.read_bytes())
        ident += f"+dirty.{h.hexdigest()[:12]}"
    return ident


def source_identity(directory: Path = PACKAGE_DIR) -> str:
    """``src:<h>``: the hash of the package's ``*.py`` files and built extensions (``*.so``)."""
    h = hashlib.sha256()
    files = sorted(p for p in directory.rglob("*") if p.is_file() and p.suffix in (".py", ".so", ".pyd")
                   and "__pycache__" not in p.parts)
    for p in files:
        h.update(str(p.relative_to(directory)).encode() + b"\0")
        h.update(p.read_bytes())
    return f"src:{h.hexdigest()[:16]}"


def _version(dist: str) -> str | None:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


@functools.lru_cache(maxsize=1)
def code_identity() -> dict:
    """The identity of the running code (module docstring), computed once per process."""
    return {"code": git_identity() or source_identity(), "jsbsim": _version("jsbsim"), "lcm": _version("lcm")}


def describe(identity: dict | None) -> str:
    """One line: ``code git:abc... (jsbsim 1.3.3, lcm 1.5.3)``; ``unrecorded`` for None."""
    if not identity:
        return "unrecorded (a record written before code identities were kept)"
    return f"code {identity.get('code')} (jsbsim {identity.get('jsbsim')}, lcm {identity.get('lcm')})"


def same(a: dict | None, b: dict | None) -> bool:
    """Whether two identities name the same code and dependency versions."""
    if not a or not b:
        return False
    return all(a.get(k) == b.get(k) for k in IDENTITY_FIELDS)
