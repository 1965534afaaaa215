"""Stress figures: surface sigma_xx along the contact over the steps, and contour maps of
sigma_xx and von Mises below the contact with the stick and slip zones marked.

matplotlib is imported only when a figure is drawn: pyplot's figure when pyplot is in use
(notebooks, galleries), else a plain Figure on an Agg canvas (files only, no pyplot import).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .output import von_mises

__all__ = ["plot_contour_maps", "plot_surface_sigma_xx"]

#: pair states as the results store them
STICK, SLIP = 1, 2


def _figure(**options):
    """A new figure (``Figure`` options): pyplot's if pyplot is in use, else a plain one."""
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        return plt.figure(**options)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(**options)
    FigureCanvasAgg(fig)
    return fig


def _close(fig) -> None:
    """Release a figure that pyplot may hold."""
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close(fig)


def plot_surface_sigma_xx(
    path: str | Path, x: np.ndarray, steps: Sequence[str], sigma_xx: np.ndarray, *, scale=None
) -> Path:
    """sigma_xx (n_steps, m) on the surface against x (m,), one line per step.

    ``scale`` = (a, p0) plots x / a and sigma_xx / p0 instead of mm and MPa.
    """
    fig = _figure(figsize=(6.4, 4.0), layout="constrained")
    ax = fig.add_subplot()
    xs, ys = (x, sigma_xx) if scale is None else (x / scale[0], sigma_xx / scale[1])
    for k, name in enumerate(steps):
        ax.plot(xs, ys[k], label=f"step {name}")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("x (mm)" if scale is None else "x / a")
    ax.set_ylabel("surface $\\sigma_{xx}$ (MPa)" if scale is None else "$\\sigma_{xx} / p_0$")
    ax.legend(fontsize=9)
    ax.set_title("Surface stress $\\sigma_{xx}$ along the contact")
    fig.savefig(path, dpi=120)
    _close(fig)
    return Path(path)


def _zones(ax, x: np.ndarray, states: np.ndarray) -> None:
    """Bars on the surface line: stick (blue) and slip (red) pairs."""
    half = 0.5 * np.diff(x).mean() if len(x) > 1 else 0.0
    for state, color, label in ((STICK, "tab:blue", "stick"), (SLIP, "tab:red", "slip")):
        sel = states == state
        if sel.any():
            ax.scatter(x[sel], np.zeros(sel.sum()), marker="s", s=12, color=color, label=label,
                       clip_on=False, zorder=5)  # fmt: skip
    ax.set_xlim(min(ax.get_xlim()[0], x.min() - half), max(ax.get_xlim()[1], x.max() + half))


def plot_contour_maps(
    path: str | Path,
    xs: np.ndarray,
    depths: np.ndarray,
    stress: np.ndarray,
    *,
    pair_x: np.ndarray,
    states: np.ndarray,
    title: str = "",
) -> Path:
    """Contours of sigma_xx and von Mises (stress (ny, nx, 4) on the grid xs x depths, depth
    downward), with the contact pairs' stick and slip zones marked on the surface."""
    from matplotlib.colors import TwoSlopeNorm

    width = np.ptp(xs) / max(np.ptp(depths), 1e-300)
    fig = _figure(figsize=(8.0, 2 * 6.2 / width + 1.2), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    fields = ((stress[..., 0], "$\\sigma_{xx}$ (MPa)", "RdBu_r"),
              (von_mises(stress), "von Mises (MPa)", "viridis"))  # fmt: skip
    for ax, (field, label, cmap) in zip(axes, fields, strict=True):
        norm = None
        if cmap == "RdBu_r":  # zero white, tension red, compression blue, each to its extreme
            low, high = min(field.min(), -1e-9), max(field.max(), 1e-9)
            levels = np.unique(np.concatenate([np.linspace(low, 0, 13), np.linspace(0, high, 9)]))
            norm = TwoSlopeNorm(0.0, low, high)
        else:
            levels = np.linspace(0.0, field.max(), 25)
        cs = ax.contourf(xs, -depths, field, levels=levels, cmap=cmap, norm=norm)
        ax.contour(xs, -depths, field, levels=levels[::3], colors="k", linewidths=0.3)
        fig.colorbar(cs, ax=ax, label=label, shrink=0.9)
        inside = (pair_x >= xs.min()) & (pair_x <= xs.max())
        _zones(ax, pair_x[inside], states[inside])
        ax.set_aspect("equal")
        ax.set_ylabel("y below the surface (mm)")
    axes[1].set_xlabel("x (mm)")
    axes[0].legend(loc="lower left", fontsize=9)
    if title:
        fig.suptitle(title)
    fig.savefig(path, dpi=120)
    _close(fig)
    return Path(path)
