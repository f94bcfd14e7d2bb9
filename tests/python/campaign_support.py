"""Test support shared by the campaign tests."""
from __future__ import annotations

from f16mmae.campaign.engine.executor import InlineExecutor


class CountingExecutor(InlineExecutor):
    """Runs in this process and counts the runs submitted (a resumed campaign submits none)."""

    def __init__(self):
        self.submitted = 0

    def submit(self, fn, /, *args, **kwargs):
        self.submitted += 1
        return super().submit(fn, *args, **kwargs)
