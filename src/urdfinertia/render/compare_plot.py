"""A PNG of per-link comparison errors, worst first, readable at a glance (matplotlib Agg).

:func:`error_series` holds the plotted numbers so that other reports can draw the same.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from urdfinertia.analysis.compare import (
    DEFAULT_TOL_COM,
    DEFAULT_TOL_INERTIA,
    LinkComparison,
    worst_first,
)

#: Most links drawn; the rest (the best ones) are counted in the title.
MAX_LINKS = 40
#: Log axes cannot show 0: each starts a decade below its smallest value, never below this.
LOG_FLOOR = 1e-6


def error_series(comparisons: Sequence[LinkComparison], tol_com: float = DEFAULT_TOL_COM,
                 tol_inertia: float = DEFAULT_TOL_INERTIA) -> dict[str, Any]:
    """Plotted numbers, worst link first; links missing a side are left out.

    Keys: ``links``, ``verdict``, ``com_distance_rel``, ``inertia_rel_error``,
    ``axis_angle_deg``, ``mass_error`` (|m_B/m_A - 1|), each a list (None where unknown),
    and ``tol_com``, ``tol_inertia``.
    """
    ranked = [c for c in worst_first(comparisons, tol_com, tol_inertia)
              if c.verdict != "missing"]

    def num(x: float | None) -> float | None:
        return float(x) if x is not None and math.isfinite(x) else None

    return {
        "links": [c.link for c in ranked],
        "verdict": [c.verdict for c in ranked],
        "com_distance_rel": [num(c.com_distance_rel) for c in ranked],
        "inertia_rel_error": [num(c.inertia_rel_error) for c in ranked],
        "axis_angle_deg": [num(c.axis_angle_deg) for c in ranked],
        "mass_error": [num(abs(c.mass_ratio - 1)) if c.mass_ratio is not None else None
                       for c in ranked],
        "tol_com": tol_com,
        "tol_inertia": tol_inertia,
    }


def _log_floor(values: list[float | None], tol: float | None) -> float:
    """A decade below the smallest positive value (or the tolerance), at least LOG_FLOOR."""
    positive = [v for v in values if v is not None and v > 0]
    if tol is not None:
        positive.append(tol)
    if not positive:
        return 0.1
    return max(LOG_FLOOR, 10 ** (math.floor(math.log10(min(positive))) - 1))


def plot_errors(comparisons: Sequence[LinkComparison], png_path: str | Path, *,
                tol_com: float = DEFAULT_TOL_COM, tol_inertia: float = DEFAULT_TOL_INERTIA,
                title: str = "") -> dict[str, Any]:
    """Write horizontal bars of each link's errors (worst at the top) to ``png_path``.

    Returns the :func:`error_series` that was drawn.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    series = error_series(comparisons, tol_com, tol_inertia)
    n_all = len(series["links"])
    n = min(n_all, MAX_LINKS)
    links = series["links"][:n]
    if n == 0:
        fig, ax = plt.subplots(figsize=(5, 1.5))
        ax.axis("off")
        ax.text(0.5, 0.5, f"{title or 'inertial comparison'}: no link has both sides",
                ha="center", va="center")
        fig.savefig(png_path, dpi=110)
        plt.close(fig)
        return series
    panels = [
        ("com_distance_rel", "CoM distance / link size", tol_com, True),
        ("inertia_rel_error", "tensor error ||dI||/||I|| (Frobenius)", tol_inertia, True),
        ("axis_angle_deg", "principal axes angle (deg)", None, False),
    ]
    if any(v is not None and v > 1e-9 for v in series["mass_error"]):
        panels.append(("mass_error", "|mass ratio - 1|", None, True))
    height = max(2.5, 0.28 * n + 1.6)
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels) + 1.5, height),
                             sharey=True, squeeze=False)
    ypos = list(range(n))
    for ax, (key, label, tol, log) in zip(axes[0], panels, strict=True):
        values = series[key][:n]
        floor = _log_floor(values, tol) if log else 0.0
        drawn = [(max(v, floor) - floor if log else v) if v is not None else 0.0
                 for v in values]
        colors = []
        for v, verdict in zip(values, series["verdict"][:n], strict=True):
            if verdict == "invalid":
                colors.append("#7f7f7f")
            elif verdict == "kept" and tol is not None and v is not None and v > tol:
                colors.append("#6baed6")  # beyond tolerance, but fix keeps it as written
            elif tol is not None and v is not None and v > tol:
                colors.append("#d62728")
            else:
                colors.append("#2ca02c" if tol is not None else "#1f77b4")
        ax.barh(ypos, drawn, color=colors, left=floor)
        if log:
            ax.set_xscale("log")
            ax.set_xlim(left=floor)
        for y, v in zip(ypos, values, strict=True):
            if v is not None:
                ax.text(max(v, floor) if log else v, y, f" {v:.2g}", va="center", fontsize=7)
        if tol is not None:
            ax.axvline(tol, color="k", linestyle="--", linewidth=1)
            ax.text(tol, -0.9, f" tol {tol:g}", fontsize=8, va="bottom")
        for y, v in zip(ypos, values, strict=True):
            if v is None:
                ax.text(floor, y, " n/a", va="center", fontsize=7)
        ax.margins(x=0.12)
        ax.set_xlabel(label)
        ax.grid(axis="x", alpha=0.3)
    axes[0][0].set_yticks(ypos)
    axes[0][0].set_yticklabels(
        [f"{name} [{v}]" if v in ("invalid", "kept") else name
         for name, v in zip(links, series["verdict"][:n], strict=True)], fontsize=8)
    axes[0][0].invert_yaxis()
    head = title or "inertial comparison"
    more = f" (worst {n} of {n_all} links)" if n_all > n else f" ({n_all} links)"
    fig.suptitle(f"{head}{more}: red = beyond tolerance, blue = beyond it but kept by fix, "
                 "grey = invalid side",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    plt.close(fig)
    return series
