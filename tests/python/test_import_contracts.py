"""The package's layers hold: the import-linter contracts of pyproject.toml
(``[tool.importlinter]``: cli -> campaign / lcm / bench -> report -> loop / design -> truth ->
banks -> names / errors; campaign kinds independent of each other and of the engine's
imports; the report importing no campaign; no import circle among the modules of any
package), checked on the installed package's import graph, imports inside functions too."""
from __future__ import annotations

import importlib
import tomllib
from pathlib import Path

from importlinter.cli import lint_imports

from f16mmae.campaign import KINDS, import_kinds
from f16mmae.report.markdown import MARKDOWN
from f16mmae.report.page import _PAGES

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def test_every_import_contract_is_kept(capsys):
    code = lint_imports(config_filename=str(PYPROJECT), no_cache=True, no_logo=True)
    out = capsys.readouterr().out
    assert code == 0, out
    assert "5 kept, 0 broken" in out


def test_the_contracts_name_every_campaign_kind_of_the_registry():
    contracts = tomllib.loads(PYPROJECT.read_text())["tool"]["importlinter"]["contracts"]
    kinds = {f"f16mmae.campaign.{k}" for k in KINDS}
    independence = next(c for c in contracts if c["type"] == "independence")
    engine = next(c for c in contracts if c.get("source_modules") == ["f16mmae.campaign.engine"])
    assert set(independence["modules"]) == kinds, "pyproject.toml's independence contract != campaign.KINDS"
    assert set(engine["forbidden_modules"]) == kinds, "pyproject.toml's engine contract != campaign.KINDS"


def test_every_kind_registers_its_pages_and_its_command():
    import_kinds()
    for kind in KINDS:
        assert kind in _PAGES and kind in MARKDOWN, kind
        cli = importlib.import_module(f"f16mmae.cli.campaign_{kind}")
        assert callable(cli.register), kind
