"""Test support shared by the campaign tests."""
from __future__ import annotations

from f16mmae.campaign.engine.executor import InlineExecutor
from f16mmae.campaign.engine.runner import run_chunk


class CountingExecutor(InlineExecutor):
    """Runs in this process and counts the runs submitted (a resumed campaign submits none):
    a task of the campaign loop (``runner.run_chunk``) counts its runs."""

    def __init__(self):
        self.submitted = 0

    def submit(self, fn, /, *args, **kwargs):
        self.submitted += len(args[1]) if fn is run_chunk else 1
        return super().submit(fn, *args, **kwargs)
