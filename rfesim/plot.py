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
    """Top tension (N) vs time, of one line or of every line: the force at the end held on
    board, as the run summary and ``rfesim run`` report it (rfesim.sweep.line_top_tension: the
    tensioner's hold for a pipelay line, the end attached to a vessel, else end B)."""
    from .sweep import line_top_tension

    ax = _new_axes(ax)
    names = [line] if line is not None else list(res.lines)
    for name in names:
        tt, where = line_top_tension(res, name)
        style = "o-" if len(res.time) == 1 else "-"
        ax.plot(res.time, tt / 1e3, style, label=f"{name} ({where})")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("top tension [kN]")
    ax.set_title("top tension")
    ax.grid(True, alpha=0.3)
    if names:
        ax.legend(fontsize="small", loc="best")
    return ax


def plot_range_graph(res, line: str, channel: str = "bend_moment", ax=None, scale: float = 1e-3,
                     unit: str = "kN*m"):
    """Range graph of a channel along a line: min, max and mean over the run vs arc length."""
    ax = _new_axes(ax)
    rg = res.line(line).range_graph(channel)
    s = rg["arc_length"]
    ax.fill_between(s, rg["min"] * scale, rg["max"] * scale, color="tab:blue", alpha=0.25, label="min - max")
    ax.plot(s, rg["mean"] * scale, color="tab:blue", lw=1.2, label="mean")
    ax.set_xlabel("arc length from end A [m]")
    ax.set_ylabel(f"{channel} [{unit}]")
    ax.set_title(f"{line}: range of {channel}")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="x-small", loc="best")
    return ax


def plot_results(res, path: str | os.PathLike | None = None, line: str | None = None):
    """A figure with the shapes of each line (or of ``line``), their range graphs of tension
    and bending moment (runs with more than one time), and their top tension vs time.

    Saves to ``path`` when given; returns the matplotlib Figure.
    """
    plt = _pyplot()
    names = [line] if line is not None else list(res.lines)
    if line is not None:
        res.line(line)  # a clear KeyError for an unknown line
    ranges = len(res.time) > 1
    per_line = 3 if ranges else 1
    nrows = max(1, per_line * len(names)) + 1
    fig, axes = plt.subplots(nrows, 1, figsize=(8.0, 3.2 * nrows), squeeze=False)
    axes = axes[:, 0]
    for j, name in enumerate(names):
        plot_line_shapes(res, name, ax=axes[per_line * j])
        if ranges:
            plot_range_graph(res, name, "tension", ax=axes[per_line * j + 1], unit="kN")
            plot_range_graph(res, name, "bend_moment", ax=axes[per_line * j + 2])
    if not names:
        axes[0].set_axis_off()
    plot_top_tension(res, line, ax=axes[-1])
    fig.tight_layout()
    if path is not None:
        fig.savefig(os.fspath(path), dpi=100)
        plt.close(fig)
    return fig
