"""What every plot of maxk shares: matplotlib on its file backend, asked for only when a
plot is drawn (it is an optional extra), and a figure written to a PNG and closed.

A leaf module (it imports nothing of maxk), so the controllers' traces, the personalities'
and the doors' plots all take it from one place: one advice when matplotlib is missing,
one resolution, no figure left open in a long-running server.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

PLOT_MISSING = ("the plot needs matplotlib: pip install 'maxk[plot]' "
                "(or pip install matplotlib)")


def pyplot() -> Any:
    """matplotlib.pyplot on the Agg backend (no display needed); ImportError with the
    advice above when matplotlib is not installed."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:
        raise ImportError(PLOT_MISSING) from exc
    return plt


def save(fig: Any, path: str | Path) -> Path:
    """Lay the figure out, write it as a PNG at 100 dpi and close it."""
    import matplotlib.pyplot as plt

    path = Path(path)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
