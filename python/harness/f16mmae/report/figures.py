"""Figure plumbing every page shares: matplotlib with the non-interactive Agg backend, writing
a figure to a PNG, and embedding a PNG in a page.  matplotlib is loaded on first use, so
importing f16mmae does not choose a backend for the caller."""
from __future__ import annotations

import base64
import html
from pathlib import Path


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path: str | Path, dpi: int = 110) -> Path:
    """Lay out, write (PNG by the suffix) and close ``fig``; returns the path."""
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)
    return path


def img_tag(path: Path, alt: str) -> str:
    if not path.exists():
        return f"<p><em>figure {html.escape(path.name)} missing</em></p>"
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<figure><img alt="{html.escape(alt)}" src="data:image/png;base64,{data}"><figcaption>{html.escape(alt)}</figcaption></figure>'
