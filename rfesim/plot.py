"""Quick-look plots of Results (matplotlib, Agg backend: no display needed).

    from rfesim.plot import plot_results
    plot_results(res, "run.png")

Helpers take ``ax=None`` (a new figure) and return the axes.
"""
from __future__ import annotations

import os
import sys

import numpy as np


def _pyplot():
    """pyplot, on the Agg backend unless the user already chose one (a notebook, a GUI)."""
    if "matplotlib.pyplot" not in sys.modules:
        import matplotlib
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _new_axes(ax):
    if ax is not None:
        return ax
    plt = _pyplot()
    _, ax = plt.subplots()
    return ax


def snapshot_indices(nt: int, count: int = 8) -> np.ndarray:
    """Indices of the first time and ``count`` evenly spaced times after it (the last included)."""
    if nt <= 0:
        return np.zeros(0, dtype=int)
    idx = np.rint(np.linspace(0, nt - 1, count + 1)).astype(int)
    return np.unique(idx)


def plot_line_shapes(res, line: str, ax=None, count: int = 8):
    """x-z shapes of one line (``position``) at the first and ``count`` evenly spaced times."""
    ax = _new_axes(ax)
    lr = res.line(line)
    idx = snapshot_indices(len(res.time), count)
    if len(idx):
        import matplotlib.cm as cm
        colors = cm.viridis(np.linspace(0.0, 1.0, len(idx)))
        for k, c in zip(idx, colors):
            p = lr.position[k]
            ax.plot(p[:, 0], p[:, 2], color=c, lw=1.2, label=f"t = {res.time[k]:.4g} s")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(f"{line}: shape")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    if len(idx):
        ax.legend(fontsize="x-small", loc="best")
    return ax


def plot_top_tension(res, line: str | None = None, ax=None):
    """Top tension (force magnitude at end B, N) vs time, of one line or of every line."""
    ax = _new_axes(ax)
    names = [line] if line is not None else list(res.lines)
    for name in names:
        tt = res.line(name).top_tension
        style = "o-" if len(res.time) == 1 else "-"
        ax.plot(res.time, tt / 1e3, style, label=name)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("top tension [kN]")
    ax.set_title("top tension (end B)")
    ax.grid(True, alpha=0.3)
    if names:
        ax.legend(fontsize="small", loc="best")
    return ax


def plot_results(res, path: str | os.PathLike | None = None, line: str | None = None):
    """A figure with the shapes of each line (or of ``line``) and their top tension vs time.

    Saves to ``path`` when given; returns the matplotlib Figure.
    """
    plt = _pyplot()
    names = [line] if line is not None else list(res.lines)
    if line is not None:
        res.line(line)  # a clear KeyError for an unknown line
    nrows = max(1, len(names)) + 1
    fig, axes = plt.subplots(nrows, 1, figsize=(8.0, 3.2 * nrows), squeeze=False)
    axes = axes[:, 0]
    for name, ax in zip(names, axes[:-1]):
        plot_line_shapes(res, name, ax=ax)
    if not names:
        axes[0].set_axis_off()
    plot_top_tension(res, line, ax=axes[-1])
    fig.tight_layout()
    if path is not None:
        fig.savefig(os.fspath(path), dpi=100)
        plt.close(fig)
    return fig
