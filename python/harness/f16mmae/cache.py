"""The user's cache root: ``$F16MMAE_CACHE_DIR``, or ``~/.cache/f16mmae``.

Everything under it is derived (designed banks, the derived aircraft, model evaluations) and
named by a hash of what it was derived from, so a stale entry is never picked up and the whole
directory may be deleted at any time."""
from __future__ import annotations

import os
from pathlib import Path


def cache_root() -> Path:
    return Path(os.environ.get("F16MMAE_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "f16mmae"))
