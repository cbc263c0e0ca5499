"""A PNG of one link's breakdown: which element carries the mass and each principal moment.

One stacked bar per quantity (mass, then the principal moments lambda1..3 in ascending
order), each split into the elements' shares in percent; cavities show as negative
segments below zero. Matplotlib with the Agg backend (no display needed).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from urdfinertia.analysis.explain import Breakdown


def share_table(breakdown: Breakdown) -> dict[str, Any]:
    """The plotted numbers: per element, its % of the mass and of each principal moment."""
    total_mass = breakdown.total.mass
    rows = []
    for eb in breakdown.elements:
        el = eb.element
        rows.append([100.0 * el.mass / total_mass, *(100.0 * np.asarray(el.share))])
    return {
        "elements": [eb.element.name for eb in breakdown.elements],
        "quantities": ["mass", "λ1", "λ2", "λ3"],
        "percent": rows,
        "moments": np.asarray(breakdown.moments).tolist(),
    }


def plot_breakdown(breakdown: Breakdown, png_path: str | Path) -> dict[str, Any]:
    """Write the stacked-bar PNG and return the numbers drawn (:func:`share_table`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    table = share_table(breakdown)
    data = np.array(table["percent"], dtype=float).reshape(len(table["elements"]), 4)
    labels = [f"mass\n{breakdown.total.mass:.4g} kg"] + [
        f"{q}\n{m:.3g} kg m²" for q, m in zip(table["quantities"][1:], table["moments"],
                                              strict=True)]
    fig, ax = plt.subplots(figsize=(8, 4.8), dpi=110)
    x = np.arange(4)
    pos = np.zeros(4)
    neg = np.zeros(4)
    colours = plt.get_cmap("tab20")(np.arange(len(data)) % 20)
    for name, row, colour in zip(table["elements"], data, colours, strict=True):
        bottom = np.where(row >= 0, pos, neg)
        ax.bar(x, row, 0.6, bottom=bottom, label=name, color=colour, edgecolor="white")
        for xi, (b, h) in enumerate(zip(bottom, row, strict=True)):
            if abs(h) >= 6:
                ax.text(xi, b + h / 2, f"{name}\n{h:.0f}%", ha="center", va="center",
                        fontsize=8)
        pos += np.where(row >= 0, row, 0)
        neg += np.where(row < 0, row, 0)
    ax.axhline(0, color="black", linewidth=0.8)
    ax.set_xticks(x, labels)
    ax.set_ylabel("share of the link total (%)")
    ax.set_title(f"link '{breakdown.link}': contributions of its elements "
                 f"({breakdown.mass_source})", fontsize=10)
    ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8, title="element")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(png_path)
    plt.close(fig)
    return table
