"""A script of ``tools/`` loaded as a module, so its tests can call its functions."""
from __future__ import annotations

import functools
import importlib.util
import pathlib

#: The repository's tools folder.
TOOLS = pathlib.Path(__file__).resolve().parents[2] / "tools"


@functools.cache
def load_tool(relative: str):
    """``tools/<relative>`` (e.g. ``"soak/scale_at_onsets.py"``) as a module, executed once per test
    session; a missing file is an error naming it."""
    path = TOOLS / relative
    if not path.is_file():
        raise FileNotFoundError(f"no tool {path}")
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
