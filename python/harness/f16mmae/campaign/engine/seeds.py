"""Seeds of campaign runs: each a pure function of the campaign's kind, its seed and the run's
place in the plan."""
from __future__ import annotations

import hashlib


def derived_seed(*parts) -> int:
    """``1 + (SHA-256("p1:p2:...") mod (2^31 - 2))``: a run's seed from its campaign kind, the
    campaign seed and its place in the plan -- deterministic, >= 1 (JSBSim maps 0 to 1),
    independent of the executor and of the order runs finish."""
    digest = hashlib.sha256(":".join(map(str, parts)).encode()).digest()
    return 1 + int.from_bytes(digest[:8], "big") % (2**31 - 2)
