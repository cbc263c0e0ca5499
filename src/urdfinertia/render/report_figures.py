"""The report's plotly figures: the 3-D view and the per-link panels of compare's numbers.

Both are coloured by what ``fix`` does (:func:`~urdfinertia.render.report_table.group`):
the links it changes in the colours of their written (orange) and new (blue) inertials,
the links it keeps in green, the others grey. Legend entries are opaque lines and squares
(the boxes' faces are nearly transparent, and so would be their swatches).
"""

from __future__ import annotations

import dataclasses
import html
from typing import TYPE_CHECKING, Any

import numpy as np

from urdfinertia.render.report_table import group

if TYPE_CHECKING:
    from urdfinertia.render.report import ReportData

#: Colours: a changed link's inertial as written and as fix writes it, a kept link's
#: inertial, the geometry of kept and of changed links.
COLORS = {"existing": "#e8710a", "recomputed": "#1a73e8", "kept": "#188038",
          "geometry": "#80868b", "changed geometry": "#f9ab00", "left": "#c5221f",
          "untouched": "#9aa0a6"}
#: Legend names of the box sources.
SOURCE_NAMES = {"existing": "as written, replaced by fix", "recomputed": "what fix writes",
                "kept": "as written, kept by fix"}
#: Opacity of the boxes' faces: low, so that the robot inside them stays visible (their
#: edges are drawn opaque).
BOX_OPACITY = 0.12
#: Longest box side drawn, times the diagonal of the robot's geometry: a wrong inertial
#: of metres must not shrink the robot to a dot (the hover text gives the real sides).
BOX_LIMIT = 1.0


def _plain(text: str) -> str:
    """Text for plotly labels, which read a subset of HTML: escape everything."""
    return html.escape(text).replace("%", "&#37;")


def _box_limit(data: ReportData) -> float | None:
    """Longest box side drawn (m): ``BOX_LIMIT`` times the diagonal of what the view shows
    besides boxes (geometry and centres of mass); None when that is a point."""
    points = [m.vertices for m in data.scene.meshes if len(m.vertices)]
    points += [b.center[None] for r in data.rows for b in r.boxes]
    if not points:
        return None
    every = np.concatenate(points).astype(np.float64)
    size = float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))
    return BOX_LIMIT * size if size > 0 else None


def _legend_square(go: Any, name: str, color: str, group_name: str) -> Any:
    """An opaque legend swatch for a group whose traces are translucent."""
    return go.Scatter3d(x=[None], y=[None], z=[None], mode="markers", name=name,
                        legendgroup=group_name, showlegend=True, hoverinfo="skip",
                        marker={"size": 12, "color": color, "symbol": "square"})


def _geometry_traces(go: Any, data: ReportData) -> list[Any]:
    changed = {r.name for r in data.rows if r.fix.changed}
    by_link: dict[str, list] = {}
    for m in data.scene.meshes:
        by_link.setdefault(m.link, []).append(m)
    traces = []
    for kind in ("geometry", "changed geometry"):
        links = [k for k in by_link if (k in changed) == (kind == "changed geometry")]
        if not links:
            continue
        label = "geometry" if kind == "geometry" else "geometry of links fix changes"
        traces.append(_legend_square(go, label, COLORS[kind], kind))
        for link in links:
            items = by_link[link]
            offsets = np.cumsum([0] + [len(m.vertices) for m in items[:-1]])
            v = np.concatenate([m.vertices for m in items])
            f = np.concatenate([m.faces + o for m, o in zip(items, offsets, strict=True)])
            # the smallest index type plotly.js reads: 2 bytes a corner for most links
            f = f.astype(np.uint16 if len(v) <= np.iinfo(np.uint16).max else np.uint32)
            traces.append(go.Mesh3d(
                x=v[:, 0], y=v[:, 1], z=v[:, 2], i=f[:, 0], j=f[:, 1], k=f[:, 2],
                name=label, legendgroup=kind, showlegend=False,
                color=COLORS[kind], opacity=0.6, flatshading=True,
                hovertemplate=f"{_plain(link)}<extra>{_plain(label)}</extra>",
            ))
    return traces


def _box_traces(go: Any, data: ReportData, source: str, limit: float | None) -> list[Any]:
    boxes = [b for r in data.rows for b in r.boxes if b.source == source]
    if not boxes:
        return []
    corners, faces, text, drawn = [], [], [], []
    for n, b in enumerate(boxes):
        flag = "<br>triangle inequality broken: a side clipped to 0" if b.clipped else ""
        sides = " x ".join(f"{x * 1000:.4g}" for x in b.lengths)
        if limit is not None and np.any(b.lengths > limit):
            # a box larger than the robot would hide it: drawn cut to the robot's size
            b = dataclasses.replace(b, lengths=np.minimum(b.lengths, limit))
            flag += f"<br>drawn cut to {limit * 1000:.4g} mm (larger than the robot)"
        drawn.append(b)
        c, f = b.triangles()
        corners.append(c)
        faces.append(f + 8 * n)
        text += [f"{_plain(b.link)}<br>{b.mass:.4g} kg, box {sides} mm{flag}"] * 8
    c, f = np.concatenate(corners), np.concatenate(faces)
    name = SOURCE_NAMES[source]
    edges = np.concatenate([b.edge_polyline() for b in drawn])
    com = np.array([b.center for b in boxes])
    return [
        # the edges carry the legend entry: an opaque line, legible beside the others
        go.Scatter3d(x=edges[:, 0], y=edges[:, 1], z=edges[:, 2], mode="lines",
                     name=name, legendgroup=source, showlegend=True, hoverinfo="skip",
                     line={"color": COLORS[source],
                           "width": 5 if source == "recomputed" else 3}),
        go.Mesh3d(x=c[:, 0], y=c[:, 1], z=c[:, 2], i=f[:, 0], j=f[:, 1], k=f[:, 2],
                  name=f"{name}: boxes", legendgroup=source, showlegend=False,
                  color=COLORS[source], opacity=BOX_OPACITY, flatshading=True,
                  hovertext=text, hovertemplate=f"%{{hovertext}}<extra>{name}</extra>"),
        go.Scatter3d(x=com[:, 0], y=com[:, 1], z=com[:, 2], mode="markers",
                     name=f"{name}: CoM", legendgroup=source, showlegend=False,
                     marker={"size": 3, "color": COLORS[source],
                             "symbol": "circle" if source == "recomputed" else "diamond"},
                     hovertext=[_plain(b.link) for b in boxes],
                     hovertemplate=f"%{{hovertext}}<br>CoM %{{x:.4f}} %{{y:.4f}} %{{z:.4f}} m"
                                   f"<extra>{name}</extra>"),
    ]


def label_points(data: ReportData) -> list[tuple[str, np.ndarray]]:
    """Where the name of each link fix changes is written: its new CoM, else its frame."""
    out = []
    for r in data.rows:
        if not r.fix.changed:
            continue
        mine = [b.center for b in r.boxes if b.source == "recomputed"]
        at = mine[0] if mine else np.asarray(data.scene.poses[r.name])[:3, 3]
        out.append((r.name, np.asarray(at, dtype=np.float64)))
    return out


#: Offsets (pixels) of successive link names from their points: around the compass, so
#: that the names of neighbouring links do not cover each other.
LABEL_OFFSETS = ((40, -40), (-40, 40), (60, 20), (-60, -20), (20, 60), (-20, -60))


def _label_offsets():  # noqa: ANN202 - an endless iterator of (dx, dy)
    import itertools

    for k, (dx, dy) in enumerate(itertools.cycle(LABEL_OFFSETS)):
        grow = 1 + (k // len(LABEL_OFFSETS)) * 0.5  # further out on each round
        yield int(dx * grow), int(dy * grow)


def scene_figure(data: ReportData) -> Any:
    """The 3-D view: geometry per link (the links fix changes tinted and named), the
    equivalent-inertia boxes and CoMs per source."""
    import plotly.graph_objects as go

    fig = go.Figure()
    limit = _box_limit(data)
    for trace in _geometry_traces(go, data):
        fig.add_trace(trace)
    for source in ("existing", "recomputed", "kept"):
        for trace in _box_traces(go, data, source, limit):
            fig.add_trace(trace)
    # the names of the links fix changes: annotations, drawn over the scene (text traces
    # would hide behind the meshes), each pointing at its link from another side
    names = [{"x": float(p[0]), "y": float(p[1]), "z": float(p[2]),
              "text": f"<b>{_plain(n)}</b>", "showarrow": True, "arrowhead": 0,
              "arrowcolor": "#3c4043", "ax": dx, "ay": dy, "font": {"size": 13,
              "color": "#202124"}, "bgcolor": "rgba(255,255,255,0.8)",
              "bordercolor": COLORS["changed geometry"], "borderwidth": 1}
             for (n, p), (dx, dy) in zip(label_points(data), _label_offsets(), strict=False)]
    geometry = [i for i, t in enumerate(fig.data)
                if t.legendgroup in ("geometry", "changed geometry") and t.type == "mesh3d"]
    buttons = [{"label": label, "method": "restyle",
                "args": [{"opacity": opacity, "visible": visible}, geometry]}
               for label, opacity, visible in (("geometry transparent", 0.6, True),
                                               ("geometry solid", 1.0, True),
                                               ("geometry hidden", 0.6, False))]
    fig.update_layout(
        scene={"aspectmode": "data", "xaxis_title": "x (m)", "yaxis_title": "y (m)",
               "zaxis_title": "z (m)", "annotations": names,
               "camera": {"eye": {"x": 1.7, "y": -1.7, "z": 1.0}}},
        height=680, margin={"l": 0, "r": 0, "t": 40, "b": 0},
        legend={"itemclick": "toggle", "groupclick": "togglegroup", "orientation": "h",
                "x": 0, "y": 0, "xanchor": "left", "yanchor": "top",
                "font": {"size": 13}},
        updatemenus=[{"type": "buttons", "direction": "right", "x": 0, "y": 1.0,
                      "xanchor": "left", "yanchor": "top", "buttons": buttons,
                      "showactive": True, "font": {"size": 12}}],
    )
    return fig


#: The panels of compare's numbers: key of ``error_series``, title, tolerance key, log axis.
ERROR_PANELS = (
    ("com_distance_rel", "CoM distance ÷ link size", "tol_com", True),
    ("inertia_rel_error", "Tensor difference (relative)", "tol_inertia", True),
    ("axis_angle_deg", "Principal axes turned (degrees)", None, False),
    ("mass_error", "Mass difference (relative)", None, True),
)
#: A panel is drawn only when some link's value exceeds this: with ``--mass keep`` every
#: mass bar would be 0 (compare's PNG leaves it out too), and principal axes turned by
#: less than a twentieth of a degree are the same axes.
SHOWN_ABOVE = {"mass_error": 1e-9, "axis_angle_deg": 0.05}


def shown_panels(series: dict) -> list[tuple[str, str, str | None, bool]]:
    """The panels drawn: those of the mass and the axes only when some link's differs."""
    return [p for p in ERROR_PANELS if p[0] not in SHOWN_ABOVE
            or any(v is not None and v > SHOWN_ABOVE[p[0]] for v in series[p[0]])]


def link_order(series: dict, data: ReportData | None) -> list[int]:
    """Indices into ``series`` (compare's, worst first) in the table's order: the links
    fix changes first (:func:`~urdfinertia.render.report_table.ranked`)."""
    if data is None:
        return list(range(len(series["links"])))
    from urdfinertia.render.report_table import ranked

    at = {r.name: k for k, r in enumerate(ranked(data.rows))}
    return sorted(range(len(series["links"])),
                  key=lambda i: at.get(series["links"][i], len(at)))


def bar_colors(series: dict, order: list[int], data: ReportData | None) -> list[str]:
    """Each bar in the colour of what fix does with its link (not of its size: fix keeps
    a plausible written value however far it is from the uniform-density geometry)."""
    groups = {r.name: group(r.fix) for r in data.rows} if data is not None else {}
    palette = {"changed": COLORS["existing"], "left": COLORS["left"],
               "kept": COLORS["kept"], "untouched": COLORS["untouched"]}
    return [palette[groups.get(series["links"][i], "untouched")] for i in order]


def error_figures(series: dict, data: ReportData | None = None) -> list[tuple[str, Any]]:
    """One figure per panel of compare's per-link numbers (``series``:
    :func:`~urdfinertia.render.compare_plot.error_series`), links in the report's order.

    Returns (panel key, figure) pairs; n/a values are left out, log axes start a decade
    below their smallest value, the tolerance is a dashed line.
    """
    import plotly.graph_objects as go

    order = link_order(series, data)
    links = [_plain(str(series["links"][i])) for i in order]
    colors = bar_colors(series, order, data)
    out = []
    for key, title, tol_key, log in shown_panels(series):
        values = [series[key][i] for i in order]
        tol = series.get(tol_key) if tol_key else None
        positive = [v for v in values if v is not None and v > 0]
        floor = max(1e-6, min(positive) / 10) if positive else 1e-6
        shown = [None if v is None else (max(v, floor) if log else v) for v in values]
        fig = go.Figure(go.Bar(
            y=links, x=shown, orientation="h", marker_color=colors, showlegend=False,
            customdata=[v if v is not None else float("nan") for v in values],
            hovertemplate=f"%{{y}}<br>{_plain(title)}: %{{customdata:.3g}}<extra></extra>"))
        if log:
            fig.update_xaxes(type="log")
        if tol is not None:
            fig.add_vline(x=tol, line_dash="dash", line_color="black",
                          annotation_text=f"tolerance {tol:g}",
                          annotation_position="top right")
        fig.update_yaxes(autorange="reversed", automargin=True)
        fig.update_layout(height=max(200, 70 + 20 * len(links)), bargap=0.25,
                          margin={"l": 10, "r": 10, "t": 24, "b": 30})
        out.append((key, fig))
    return out
