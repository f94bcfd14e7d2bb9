"""Three small campaigns (single, dual, envelope) give exactly the records and summaries
stored in ``golden/``, which the code made before the package was reshaped: same seeds, same
run keys, same declarations and probabilities (run timing aside, which is wall-clock).

The golden files were written by::

    f16mmae campaign single --runs 1 --cases NONE,LS,PIT --baseline none --workers 1
    f16mmae campaign dual --runs 1 --pairs LS+PIT --workers 1
    f16mmae campaign envelope --runs 1 --mach-alt 0.45:20000 --cases NONE,LS --workers 1

each record and the summary without ``timing``, records sorted by run key.  A change that
alters results on purpose regenerates them in the same commit and says why.  The code
identity (``code`` in every record and summary, ``codes_in_records`` in the summary) names
the commit that flew the runs, so it is checked for its form and left out of the comparison.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from f16mmae.campaign.dual import DualCampaign, run_campaign as run_dual
from f16mmae.campaign.engine.executor import InlineExecutor
from f16mmae.campaign.engine.store import ResultsStore
from f16mmae.campaign.envelope import EnvelopeCampaign, run_envelope
from f16mmae.campaign.envelope.points import parse_mach_alt
from f16mmae.campaign.single import SingleCampaign, run_campaign as run_single

GOLDEN = Path(__file__).with_name("golden")

pytestmark = pytest.mark.slow


IDENTITY_FIELDS = ("code", "codes_in_records")


def _observed(out: Path) -> dict:
    stored = ResultsStore(out).records()
    summary = json.loads((out / "summary.json").read_text())
    assert {r["code"]["code"].split(":")[0] for r in stored} <= {"git", "src"}
    assert summary["code"] == stored[0]["code"] and len(summary["codes_in_records"]) == 1
    records = [{k: v for k, v in r.items() if k not in ("timing",) + IDENTITY_FIELDS} for r in stored]
    for k in ("timing",) + IDENTITY_FIELDS:
        summary.pop(k)
    return {"records": sorted(records, key=lambda r: r["run_key"]), "summary": summary}


def _check(kind: str, out: Path) -> None:
    golden = json.loads((GOLDEN / f"campaign_{kind}.json").read_text())
    observed = json.loads(json.dumps(_observed(out)))  # tuples as lists, as in the file
    assert [r["run_key"] for r in observed["records"]] == [r["run_key"] for r in golden["records"]]
    for seen, want in zip(observed["records"], golden["records"]):
        assert seen == want, f"record {want['run_key']} differs"
    assert observed["summary"] == golden["summary"]


def test_single_campaign_matches_its_golden_records(tmp_path):
    cfg = SingleCampaign(runs=1, cases=("NONE", "LS", "PIT"), baseline=None)
    run_single(cfg, tmp_path, InlineExecutor(), show_progress=False, measure_cost=False)
    _check("single", tmp_path)


def test_dual_campaign_matches_its_golden_records(tmp_path):
    run_dual(DualCampaign(runs=1, pairs=(("LS", "PIT"),)), tmp_path, InlineExecutor(), show_progress=False)
    _check("dual", tmp_path)


def test_envelope_campaign_matches_its_golden_records(tmp_path):
    cfg = EnvelopeCampaign(runs=1, points=parse_mach_alt("0.45:20000"), cases=("NONE", "LS"))
    run_envelope(cfg, tmp_path, InlineExecutor(), show_progress=False)
    _check("envelope", tmp_path)
