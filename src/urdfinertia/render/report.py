"""The ``report`` job: one self-contained HTML page a person can look at.

It holds a 3-D view of the robot at its zero configuration with the equivalent-inertia
boxes of the existing and the recomputed inertials (:mod:`report_scene`), the per-link
error plot of ``compare`` and a per-link table. plotly.js is inlined and MathJax left out,
so the page loads nothing from the network and works offline.
"""

from __future__ import annotations

import dataclasses
import html
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from urdfinertia import __version__
from urdfinertia.analysis.check import Finding, check_description
from urdfinertia.analysis.compare import LinkComparison, compare_with_geometry, summary
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.formats import read_description
from urdfinertia.errors import require_extra
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.link.fix import fix_robot
from urdfinertia.link.options import FixOptions
from urdfinertia.link.policy import every_link
from urdfinertia.link.results import FixResult, LinkResult, Status
from urdfinertia.render.compare_plot import error_series
from urdfinertia.render.scene import (
    DEFAULT_VIEW_FACES,
    InertiaBox,
    Scene,
    build_scene,
    equivalent_box,
    existing_mass_properties,
)

#: Colours of the two inertial sources and of the geometry.
COLORS = {"existing": "#e8710a", "recomputed": "#1a73e8", "geometry": "#80868b"}
#: Opacity of the boxes' faces: low, so that the robot inside them stays visible (their
#: edges are drawn opaque).
BOX_OPACITY = 0.12
#: Longest box side drawn, times the diagonal of the robot's geometry: a wrong inertial
#: of metres must not shrink the robot to a dot (the hover text gives the real sides).
BOX_LIMIT = 1.0
#: plotly config: no logo link, no fetches (topojson is only for geo maps, never needed).
PLOTLY_CONFIG = {"displaylogo": False, "responsive": True, "topojsonURL": "",
                 "toImageButtonOptions": {"format": "png", "scale": 2}}


#: What drawing the page needs beyond the core install: the ``report`` extra.
REPORT_MODULES = ("plotly",)


def require_report_extra() -> None:
    """Raise :class:`~urdfinertia.errors.MissingExtraError` (an ImportError) naming
    ``pip install 'urdfinertia[report]'`` when plotly is not installed."""
    require_extra(REPORT_MODULES, "the report")


@dataclass(frozen=True, eq=False)
class LinkRow:
    """Everything the report says about one link."""

    name: str
    existing: MassProperties | None
    existing_note: str  # why ``existing`` is None, or ""
    fix: LinkResult
    comparison: LinkComparison | None
    findings: tuple[Finding, ...]
    boxes: tuple[InertiaBox, ...]

    @property
    def recomputed(self) -> MassProperties | None:
        """What ``fix`` writes for the link when it changes it (None: kept as written)."""
        return self.fix.after if self.fix.changed else None


@dataclass(frozen=True, eq=False)
class ReportData:
    """The report's content: ``fix`` is the default fix (its verdicts and what it writes),
    ``geometry`` every link computed from its geometry (compare's side B)."""

    fix: FixResult
    options: FixOptions
    rows: tuple[LinkRow, ...]
    scene: Scene
    robot_findings: tuple[Finding, ...]  # those with no link
    summary: dict  # compare.summary
    error_series: dict  # compare_plot.error_series


def collect(path: str | Path, options: FixOptions, *, view: str = "visual",
            face_budget: int = DEFAULT_VIEW_FACES,
            meshes: MeshLibrary | None = None) -> ReportData:
    """Run fix, compare and check on ``path`` and build the 3-D scene.

    The links' verdicts are ``fix``'s (the same objects ``check`` and ``compare`` render):
    the recomputed values shown are what ``fix`` writes, the findings ``check``'s.
    The file is read leniently (non-finite inertial values are kept) so that a broken
    inertial shows up as invalid in the report instead of stopping it. ``meshes``
    (default :func:`~urdfinertia.cache.library.mesh_library`) may hold results computed
    by worker processes.
    """
    require_report_extra()  # before the work, not after it
    robot, data = read_description(path, lenient=True)
    if meshes is None:
        meshes = mesh_library(options.package_dirs, options.max_faces)
    checked = check_description(robot, meshes=meshes, options=options)
    fix = FixResult(robot.path or Path(path), robot, checked.links, data, data)
    geometry = fix_robot(robot, data, every_link(options), meshes)  # compare's side B
    comparisons = compare_with_geometry(path, options, fix_result=geometry,
                                        verdicts=checked.links, meshes=meshes)
    findings = checked.findings
    scene = build_scene(robot, meshes, view=view, face_budget=face_budget)
    by_link = {c.link: c for c in comparisons}
    rows = []
    for link, result in zip(robot.links, fix.links, strict=True):
        existing, why = existing_mass_properties(link.inertial)
        pose = scene.poses[link.name]
        boxes = []
        if existing is not None:
            boxes.append(equivalent_box(existing, pose, link.name, "existing"))
        if result.changed and result.after is not None:
            boxes.append(equivalent_box(result.after, pose, link.name, "recomputed"))
        mine = tuple(f for f in findings if f.link == link.name)
        rows.append(LinkRow(link.name, existing, why, result, by_link.get(link.name), mine,
                            tuple(boxes)))
    robot_findings = tuple(f for f in findings if f.link is None)
    return ReportData(fix, options, tuple(rows), scene, robot_findings,
                      summary(comparisons), error_series(comparisons))


# --- figures ----------------------------------------------------------------------------
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


def scene_figure(data: ReportData):
    """The 3-D view: one geometry trace per link, boxes and CoMs per source."""
    import plotly.graph_objects as go

    fig = go.Figure()
    limit = _box_limit(data)
    by_link: dict[str, list] = {}
    for m in data.scene.meshes:
        by_link.setdefault(m.link, []).append(m)
    first = True
    for link, items in by_link.items():
        offsets = np.cumsum([0] + [len(m.vertices) for m in items[:-1]])
        v = np.concatenate([m.vertices for m in items])
        f = np.concatenate([m.faces + o for m, o in zip(items, offsets, strict=True)])
        # the smallest index type plotly.js reads: 2 bytes a corner for most links
        f = f.astype(np.uint16 if len(v) <= np.iinfo(np.uint16).max else np.uint32)
        fig.add_trace(go.Mesh3d(
            x=v[:, 0], y=v[:, 1], z=v[:, 2], i=f[:, 0], j=f[:, 1], k=f[:, 2],
            name="geometry", legendgroup="geometry", showlegend=first,
            color=COLORS["geometry"], opacity=0.6, flatshading=True,
            hovertemplate=f"{_plain(link)}<extra>geometry</extra>",
        ))
        first = False
    for source in ("existing", "recomputed"):
        boxes = [b for r in data.rows for b in r.boxes if b.source == source]
        if not boxes:
            continue
        corners, faces, text = [], [], []
        drawn = []
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
        fig.add_trace(go.Mesh3d(
            x=c[:, 0], y=c[:, 1], z=c[:, 2], i=f[:, 0], j=f[:, 1], k=f[:, 2],
            name=f"{source} inertia boxes", legendgroup=source, showlegend=True,
            color=COLORS[source], opacity=BOX_OPACITY, flatshading=True, hovertext=text,
            hovertemplate=f"%{{hovertext}}<extra>{source}</extra>",
        ))
        edges = np.concatenate([b.edge_polyline() for b in drawn])
        fig.add_trace(go.Scatter3d(
            x=edges[:, 0], y=edges[:, 1], z=edges[:, 2], mode="lines",
            name=f"{source} box edges", legendgroup=source, showlegend=False,
            line={"color": COLORS[source], "width": 3}, hoverinfo="skip",
        ))
        com = np.array([b.center for b in boxes])
        fig.add_trace(go.Scatter3d(
            x=com[:, 0], y=com[:, 1], z=com[:, 2], mode="markers",
            name=f"{source} CoM", legendgroup=source, showlegend=False,
            marker={"size": 3, "color": COLORS[source],
                    "symbol": "diamond" if source == "existing" else "circle"},
            hovertext=[_plain(b.link) for b in boxes],
            hovertemplate=f"%{{hovertext}}<br>CoM %{{x:.4f}} %{{y:.4f}} %{{z:.4f}} m"
                          f"<extra>{source}</extra>",
        ))
    geometry = [i for i, t in enumerate(fig.data) if t.legendgroup == "geometry"]
    buttons = [{"label": label, "method": "restyle",
                "args": [{"opacity": opacity, "visible": visible}, geometry]}
               for label, opacity, visible in (("geometry transparent", 0.6, True),
                                               ("geometry solid", 1.0, True),
                                               ("geometry hidden", 0.6, False))]
    fig.update_layout(
        scene={"aspectmode": "data", "xaxis_title": "x (m)", "yaxis_title": "y (m)",
               "zaxis_title": "z (m)", "camera": {"eye": {"x": 1.9, "y": -1.9, "z": 1.1}}},
        height=720, margin={"l": 0, "r": 0, "t": 30, "b": 0},
        legend={"itemclick": "toggle", "title": {"text": "click to show/hide"}},
        updatemenus=[{"type": "buttons", "direction": "right", "x": 0, "y": 1.04,
                      "xanchor": "left", "buttons": buttons, "showactive": True}],
    )
    return fig


#: The panels of the error plot: key of ``error_series``, title, tolerance key, log axis.
ERROR_PANELS = (
    ("com_distance_rel", "CoM distance / link size", "tol_com", True),
    ("inertia_rel_error", "tensor error ||dI||/||I|| (Frobenius)", "tol_inertia", True),
    ("axis_angle_deg", "principal axes angle (deg)", None, False),
    ("mass_error", "|mass ratio - 1|", None, True),
)
#: The mass panel is drawn only when some link's mass changed by more than this (as
#: compare's PNG does): with ``--mass keep`` every bar would be 0.
MASS_ERROR_SHOWN = 1e-9


def error_figure(series: dict):
    """The per-link errors of ``compare`` (the numbers of its PNG), worst link on top.

    Red: beyond tolerance, green: within, grey: a side is invalid; n/a values are left out.
    The mass panel is left out when no mass changed.
    """
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    links = [_plain(str(x)) for x in series["links"]]
    verdicts = series["verdict"]
    panels = [p for p in ERROR_PANELS if p[0] != "mass_error"
              or any(v is not None and v > MASS_ERROR_SHOWN for v in series[p[0]])]
    fig = make_subplots(rows=1, cols=len(panels), shared_yaxes=True,
                        horizontal_spacing=0.03,
                        subplot_titles=[title for _, title, _, _ in panels])
    for col, (key, title, tol_key, log) in enumerate(panels, start=1):
        values = series[key]
        tol = series.get(tol_key) if tol_key else None
        positive = [v for v in values if v is not None and v > 0]
        floor = max(1e-6, min(positive) / 10) if positive else 1e-6
        shown = [None if v is None else (max(v, floor) if log else v) for v in values]
        colors = ["#7f7f7f" if verdict == "invalid" else
                  "#d62728" if tol is not None and v is not None and v > tol else
                  "#2ca02c" if tol is not None else COLORS["recomputed"]
                  for v, verdict in zip(values, verdicts, strict=True)]
        fig.add_trace(go.Bar(
            y=links, x=shown, orientation="h", marker_color=colors, showlegend=False,
            customdata=[v if v is not None else float("nan") for v in values],
            hovertemplate=f"%{{y}}<br>{title}: %{{customdata:.3g}}<extra></extra>",
        ), row=1, col=col)
        if log:
            fig.update_xaxes(type="log", row=1, col=col)
        if tol is not None:
            fig.add_vline(x=tol, line_dash="dash", line_color="black", row=1, col=col,
                          annotation_text=f"tol {tol:g}", annotation_position="bottom right")
    fig.update_yaxes(autorange="reversed", automargin=True)
    fig.update_layout(height=max(260, 90 + 18 * len(links)), bargap=0.25,
                      margin={"l": 10, "r": 20, "t": 40, "b": 30})
    return fig


# --- table and page ---------------------------------------------------------------------
def _g(x: float) -> str:
    return f"{x:.4g}"


def _vec(v) -> str:
    return " ".join(_g(float(x)) for x in v)


def _pair(existing: str, recomputed: str) -> str:
    return (f'<span class="e">E</span> {existing}<br>'
            f'<span class="r">R</span> {recomputed}')


def _mass_cells(row: LinkRow) -> list[str]:
    """Mass, CoM and principal moments, existing (as written, even if invalid) over
    recomputed."""
    prev, r = row.fix.previous, row.recomputed
    if prev is None:
        existing = ["no &lt;inertial&gt;"] * 3
    else:
        moments = (row.existing.principal()[0] if row.existing is not None else
                   getattr(row.comparison, "moments_a", None))
        existing = [_g(prev.mass), _vec(prev.origin.xyz),
                    _vec(moments) if moments is not None else "-"]
        if row.existing is None:
            existing[0] += f' <span class="bad">{html.escape(row.existing_note)}</span>'
    recomputed = ((["kept"] if prev is not None else ["-"]) * 3 if r is None else
                  [_g(r.mass), _vec(r.com), _vec(r.principal()[0])])
    return [_pair(e, x) for e, x in zip(existing, recomputed, strict=True)]


def _errors_cell(c: LinkComparison | None) -> str:
    if c is None:
        return "-"
    parts = []
    for label, value, fmt in (("mass ratio", c.mass_ratio, _g),
                              ("CoM shift", c.com_distance, lambda x: f"{x * 1000:.3g} mm"),
                              ("CoM shift / size", c.com_distance_rel, _g),
                              ("tensor error", c.inertia_rel_error, _g),
                              ("axes angle", c.axis_angle_deg, lambda x: f"{x:.3g}°")):
        if value is not None and np.isfinite(value):
            parts.append(f"{label} {html.escape(fmt(value))}")
    if c.note:
        parts.append(f"<i>{html.escape(c.note)}</i>")
    verdict = html.escape(c.verdict)
    return f'<span class="v v-{verdict}">{verdict}</span><br>' + "<br>".join(parts)


def _finding(f: Finding) -> str:
    severity = str(f.severity)
    return (f'<span class="s s-{html.escape(severity)}">{html.escape(severity)}</span> '
            f"{html.escape(str(f.code))}: {html.escape(str(f.message))}")


def _geometry_cell(row: LinkRow) -> str:
    a = row.fix.assembly
    if a is None:
        return html.escape(row.fix.geometry)
    methods = sorted({p.part.method for p in a.parts})
    n = len(a.parts)
    return html.escape(f"{row.fix.geometry}: {n} part{'s' if n != 1 else ''} "
                       f"({', '.join(methods)})")


def _notes_cell(row: LinkRow) -> str:
    notes = []
    if row.fix.decision:
        notes.append(f"fix: {row.fix.decision}")
    if row.fix.assembly is not None:
        notes.append(f"mass: {row.fix.assembly.mass_source}")
    notes += list(row.fix.warnings)
    notes += [f"{b.source} tensor breaks the triangle inequality: its box has a side "
              "clipped to 0" for b in row.boxes if b.clipped]
    return "<br>".join(html.escape(n) for n in notes)


#: Share of the page width of each column of the link table (percent): fixed, so the
#: table never scrolls sideways; long words and number lists wrap inside their cells.
COLUMN_WIDTHS = (9, 13, 9, 13, 14, 13, 14, 15)


def table_html(rows: Sequence[LinkRow]) -> str:
    head = ("link", "geometry used", "mass kg", "CoM m (link frame)",
            "principal moments kg m²", "errors (compare)", "check findings",
            "mass source, repairs, fallbacks")
    out = ['<table id="links"><colgroup>']
    out += [f'<col style="width:{w}%">' for w in COLUMN_WIDTHS]
    out.append("</colgroup><thead><tr>")
    out += [f"<th>{h}</th>" for h in head]
    out.append("</tr></thead><tbody>")
    for row in rows:
        verdict = row.comparison.verdict if row.comparison is not None else ""
        cells = [f'<td class="name">{html.escape(row.name)}</td>',
                 f"<td>{_geometry_cell(row)}</td>"]
        cells += [f'<td class="num">{c}</td>' for c in _mass_cells(row)]
        cells.append(f'<td class="wide">{_errors_cell(row.comparison)}</td>')
        cells.append('<td class="wide">' + "<br>".join(_finding(f) for f in row.findings)
                     + "</td>")
        cells.append(f'<td class="wide">{_notes_cell(row)}</td>')
        out.append(f'<tr class="v-{html.escape(verdict)}">' + "".join(cells) + "</tr>")
    out.append("</tbody></table>")
    return "".join(out)


_CSS = """
body{font-family:system-ui,sans-serif;margin:1.5em;color:#202124}
h1{font-size:1.5em;margin-bottom:.2em} h2{font-size:1.2em;margin-top:1.5em}
.meta{color:#5f6368;font-size:.9em}
table{border-collapse:collapse;font-size:.82em;width:100%;table-layout:fixed}
th,td{border:1px solid #dadce0;padding:3px 6px;vertical-align:top;text-align:left;
overflow-wrap:anywhere}
th{background:#f1f3f4;position:sticky;top:0}
td.num{font-family:ui-monospace,monospace;font-size:.95em}
td.name{font-weight:600}
.e{color:#e8710a;font-weight:700} .r{color:#1a73e8;font-weight:700}
.bad{color:#c5221f}
.v,.s{border-radius:3px;padding:0 4px;font-weight:600;background:#e8eaed}
.v-ok{background:#ceead6} .v-differs,.v-warning{background:#feefc3}
.v-wrong,.v-invalid,.s-error{background:#fad2cf}
ul.notes{color:#5f6368}
"""

def _summary_html(data: ReportData) -> str:
    n = len(data.rows)
    counts = {s: sum(r.fix.status == s for r in data.rows) for s in Status}
    verdicts = ", ".join(f"{k} {v}" for k, v in data.summary.get("verdicts", {}).items())
    findings = [f for r in data.rows for f in r.findings] + list(data.robot_findings)
    severities = ", ".join(f"{sev} {sum(f.severity == sev for f in findings)}"
                           for sev in ("error", "warning", "info"))
    medians = data.summary.get("median", {})
    median = ", ".join(f"{k} {v:.3g}" for k, v in medians.items() if v is not None)
    items = [html.escape(x) for x in (
        f"{n} links: fix recomputes {counts[Status.RECOMPUTED]}, repairs "
        f"{counts[Status.REPAIRED]} and keeps the others as written",
        f"compare verdicts: {verdicts or 'none'}" + (f" (medians: {median})" if median else ""),
        f"check findings: {severities}",
        f"3-D view: {len(data.scene.meshes)} elements, {data.scene.face_count} faces "
        "(meshes decimated for display only; the numbers use the full meshes)",
        *data.scene.notes)]
    items += [_finding(f) for f in data.robot_findings]
    opts = data.options
    meta = html.escape(f"{data.fix.path} · geometry {opts.geometry}, mass {opts.mass}, "
                       f"density {opts.density:g} kg/m³"
                       f"{', spec' if opts.spec is not None else ''} · "
                       f"urdf-inertia {__version__}")
    return f'<p class="meta">{meta}</p><ul>' + "".join(f"<li>{i}</li>" for i in items) + "</ul>"


def _plot_div(div_id: str, fig) -> str:
    return (f'<div id="{div_id}" class="plot" '
            f'style="height:{int(fig.layout.height or 500)}px;width:100%"></div>')


def _plotly_loader() -> str:
    """A script that defines ``window.urdfInertiaPlotly``: a promise of plotly.js loaded.

    plotly.js (4.8 MB) is inlined gzip-compressed and base64-encoded (2 MB) and unpacked
    by the browser's ``DecompressionStream``: the page stays one self-contained file,
    less than half the size. Its licence header stays readable at the top.
    """
    import base64
    import gzip

    from plotly.offline import get_plotlyjs

    source = get_plotlyjs()
    end = source.find("*/")
    header = source[:end + 2] if source.startswith("/**") and end > 0 else ""
    packed = base64.b64encode(gzip.compress(source.encode("utf-8"), 9, mtime=0)).decode()
    return (f'<script type="text/javascript">{header}\n'
            "window.urdfInertiaPlotly = (function () {\n"
            f'  var text = atob("{packed}");\n'
            "  var bytes = new Uint8Array(text.length);\n"
            "  for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);\n"
            "  var plain = new Blob([bytes]).stream()"
            '.pipeThrough(new DecompressionStream("gzip"));\n'
            "  return new Response(plain).text().then(function (js) {\n"
            '    var el = document.createElement("script");\n'
            "    el.text = js;\n"
            "    document.head.appendChild(el);\n"
            "  });\n"
            "})();</script>")


def _plots_script(figures: dict) -> str:
    """plotly.js (inlined, :func:`_plotly_loader`) and the code that draws ``figures``
    (div id -> figure).

    It goes at the end of the page so that the text and the table show before plotly.js
    is unpacked and parsed. Each finished plot increments ``window.urdfInertiaRendered``
    (tests and scripts/bench_report.py wait for it to reach ``body[data-figures]``).
    """
    import plotly.io as pio

    # JSON holds "<" only inside strings, where \u003c means the same: no "</script>".
    specs = ",".join(f"{json.dumps(k)}:{pio.to_json(f, validate=False)}"
                     for k, f in figures.items()).replace("<", "\\u003c")
    config = json.dumps(PLOTLY_CONFIG)
    return (_plotly_loader() + "\n"
            '<script type="text/javascript">(function () {\n'
            f"var figures = {{{specs}}};\nvar config = {config};\n"
            "window.urdfInertiaPlotly.then(function () {\n"
            "Object.keys(figures).forEach(function (id) {\n"
            "  Plotly.newPlot(id, figures[id].data, figures[id].layout, config)"
            ".then(function () {\n"
            "    window.urdfInertiaRendered = (window.urdfInertiaRendered || 0) + 1;\n"
            "    window.urdfInertiaRenderedAt = performance.now();\n"
            "  });\n});\n});\n})();</script>")


def render_html(data: ReportData) -> str:
    """The whole page as one string (plotly.js inlined once, a few MB)."""
    require_report_extra()
    name = html.escape(data.fix.robot.name or Path(data.fix.path).stem)
    figures = {"view3d": scene_figure(data)}
    if data.error_series["links"]:
        figures["errors"] = error_figure(data.error_series)
    parts = [
        "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
        f"<title>urdf-inertia report: {name}</title><style>{_CSS}</style></head>",
        f'<body data-figures="{len(figures)}"><h1>Inertia report: {name}</h1>',
        _summary_html(data),
        "<h2>3-D view at the zero configuration</h2>",
        '<p class="meta">Each box is the uniform box with the link\'s mass and principal '
        'moments, along the principal axes and centred at the CoM: <span class="e">'
        'existing</span> and <span class="r">recomputed</span>. Click a legend entry to '
        "show or hide a group; drag to rotate, scroll to zoom.</p>",
        _plot_div("view3d", figures["view3d"]),
        "<h2>Per-link errors (compare), worst first</h2>",
        _plot_div("errors", figures["errors"]) if "errors" in figures else
        '<p class="meta">No link has both an existing and a recomputed inertial.</p>',
        "<h2>Links</h2>",
        '<p class="meta"><span class="e">E</span> existing inertial as written, '
        '<span class="r">R</span> recomputed from the geometry; inertia about the '
        "CoM along the link frame's axes.</p>",
        table_html(data.rows),
        _plots_script(figures),
        "</body></html>",
    ]
    return "\n".join(parts)


def build_report(path: str | Path, options: FixOptions, *, view: str = "visual",
                 face_budget: int = DEFAULT_VIEW_FACES,
                 meshes: MeshLibrary | None = None) -> str:
    """The report of ``path`` as an HTML string (``meshes``: see :func:`collect`)."""
    return render_html(collect(path, options, view=view, face_budget=face_budget,
                               meshes=meshes))
