"""The one base class of every error f16mmae reports to a user.

Each part raises its own subclass (``CampaignError``, ``HilError``, ...), named where the part
lives; a command catches :class:`F16mmaeError` and prints its message, which names the bad
file, field or value and the valid choices.
"""
from __future__ import annotations


class F16mmaeError(Exception):
    """A user-facing error: the message says what is wrong and what is valid."""
