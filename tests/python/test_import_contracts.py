"""The package's layers hold: the import-linter contracts of pyproject.toml
(``[tool.importlinter]``: cli -> campaign / lcm / bench -> report -> loop / design -> truth ->
banks -> names / errors; campaign kinds independent of each other and of the engine's
imports; the report importing no campaign; no import circle among the modules of any
package), checked on the installed package's import graph, imports inside functions too."""
from __future__ import annotations

from pathlib import Path

from importlinter.cli import lint_imports

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def test_every_import_contract_is_kept(capsys):
    code = lint_imports(config_filename=str(PYPROJECT), no_cache=True, no_logo=True)
    out = capsys.readouterr().out
    assert code == 0, out
    assert "5 kept, 0 broken" in out
