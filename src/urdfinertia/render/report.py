"""The `report` job: one self-contained HTML page a person can look at.

It holds a 3-D view of the robot at its zero configuration with the equivalent-inertia
boxes of the existing and the recomputed inertials (`urdfinertia.render.scene`), the per-link
error plot of `compare` and a per-link table. plotly.js is inlined and MathJax left out,
so the page loads nothing from the network and works offline.
"""

from __future__ import annotations

import html
import json
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from urdfinertia import __version__
from urdfinertia.analysis.check import Finding, check_description
from urdfinertia.analysis.compare import LinkComparison, compare_with_geometry, summary
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.formats import read_description
from urdfinertia.errors import require_extra
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.plan.fix import fix_robot
from urdfinertia.plan.policy import every_link
from urdfinertia.plan.results import FixResult, LinkResult, Status
from urdfinertia.render.compare_plot import error_series
from urdfinertia.render.report_figures import (  # noqa: F401 - this module's API too
    BOX_LIMIT,
    BOX_OPACITY,
    COLORS,
    ERROR_PANELS,
    error_figures,
    scene_figure,
)
from urdfinertia.render.report_table import (
    STATUS_WORDS,
    finding_html,
    group,
    percent,
    ranked,
    table_html,
)
from urdfinertia.render.scene import (
    DEFAULT_VIEW_FACES,
    InertiaBox,
    Scene,
    build_scene,
    equivalent_box,
    existing_mass_properties,
)

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
    """The report's content: `fix` is the default fix (its verdicts and what it writes),
    `geometry` every link computed from its geometry (compare's side B).

    Attributes
    ----------
    fix : FixResult
        The default fix: its verdicts and what it writes.
    options : FixOptions
        The options the report was made with.
    rows : tuple of LinkRow
        Everything the report says about each link, in document order.
    scene : Scene
        The 3-D view: the robot at its zero configuration, and the inertia boxes.
    robot_findings : tuple of Finding
        The findings with no link.
    summary : dict
        `compare`'s summary of the links (`urdfinertia.analysis.compare.summary`).
    error_series : dict
        The per-link error plot's data (`urdfinertia.render.compare_plot.error_series`).
    """

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
    robot, data = read_description(path)
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
        if existing is not None:  # as written: replaced by fix, or kept
            boxes.append(equivalent_box(existing, pose, link.name,
                                        "existing" if result.changed else "kept"))
        if result.changed and result.after is not None:
            boxes.append(equivalent_box(result.after, pose, link.name, "recomputed"))
        mine = tuple(f for f in findings if f.link == link.name)
        rows.append(LinkRow(link.name, existing, why, result, by_link.get(link.name), mine,
                            tuple(boxes)))
    robot_findings = tuple(f for f in findings if f.link is None)
    return ReportData(fix, options, tuple(rows), scene, robot_findings,
                      summary(comparisons), error_series(comparisons))


# --- the page -----------------------------------------------------------------------
_CSS = """
body{font-family:system-ui,sans-serif;margin:1.5em;color:#202124;max-width:1800px}
h1{font-size:1.5em;margin-bottom:.2em} h2{font-size:1.2em;margin-top:1.5em}
h3{font-size:1em;margin:.2em 0;font-weight:600}
.meta{color:#5f6368;font-size:.9em}
.verdict{border-left:4px solid #e8710a;background:#fef7e0;padding:.5em 1em;margin:.8em 0}
.verdict p{margin:.3em 0}
table{border-collapse:collapse;font-size:.82em;width:100%;table-layout:fixed}
th,td{border:1px solid #dadce0;padding:3px 6px;vertical-align:top;text-align:left;
overflow-wrap:anywhere}
th{background:#f1f3f4;position:sticky;top:0;z-index:1}
td.num{font-family:ui-monospace,monospace;font-size:.95em}
td.name{font-weight:600}
.e{color:#b45309;font-weight:600;font-size:.9em} .r{color:#1a73e8;font-weight:600;font-size:.9em}
.bad{color:#c5221f}
.v,.s{border-radius:3px;padding:0 4px;font-weight:600;background:#e8eaed;white-space:nowrap}
.v-changed{background:#fde2c4} .v-left,.s-error{background:#fad2cf}
.v-kept{background:#ceead6} .s-warning{background:#feefc3}
tr.g-changed td:first-child{border-left:4px solid #e8710a}
tr.g-left td:first-child{border-left:4px solid #c5221f}
tr.g-untouched{color:#5f6368}
details summary{cursor:pointer} details{margin:1px 0}
.sw{display:inline-block;width:.9em;height:.9em;border-radius:2px;vertical-align:-.1em;
margin:0 .25em 0 .6em}
.view{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start}
.view .plot{flex:1 1 640px;min-width:0}
.view aside{flex:1 1 240px;max-width:360px;max-height:640px;overflow:auto;font-size:.85em;
border:1px solid #dadce0;padding:.4em .6em}
aside ol{margin:.2em 0;padding-left:1.6em} aside li{margin:.1em 0}
.panels{display:grid;grid-template-columns:repeat(auto-fit,minmax(330px,1fr));gap:12px}
@media (max-width:1100px){
 #links,#links tbody,#links tr,#links td{display:block;width:auto}
 #links colgroup,#links thead{display:none}
 #links tr{border:1px solid #dadce0;margin:0 0 .8em;border-left-width:4px}
 #links td{border:0;border-top:1px solid #f1f3f4;display:grid;
  grid-template-columns:11em minmax(0,1fr);gap:.6em}
 #links td::before{content:attr(data-label);font-weight:600;color:#5f6368;
  font-family:system-ui,sans-serif;font-size:.82rem}
 #links td.name{font-size:1.1em;background:#f8f9fa}
 tr.g-changed td:first-child,tr.g-left td:first-child{border-left:0}
 #links tr.g-changed{border-left-color:#e8710a} #links tr.g-left{border-left-color:#c5221f}
}
"""


def _names(rows: Sequence[LinkRow], limit: int = 12) -> str:
    names = [r.name for r in rows]
    more = f" and {len(names) - limit} more" if len(names) > limit else ""
    return ", ".join(names[:limit]) + more


def _verdict_html(data: ReportData) -> str:
    """What fix does, first: the links it changes (named), keeps, cannot compute."""
    rows = ranked(data.rows)
    n = len(rows)
    changed = [r for r in rows if r.fix.changed]
    left = [r for r in rows if r.fix.status == Status.LEFT]
    kept = [r for r in rows if r.fix.status == Status.KEPT]
    others = n - len(changed) - len(left) - len(kept)
    lines = []
    if changed:
        by = Counter(STATUS_WORDS[r.fix.status] for r in changed)
        how = ", ".join(f"{k} {v}" for k, v in by.items())
        lines.append(f"<b>fix changes {len(changed)} of {n} links</b> ({how}): "
                     f"{html.escape(_names(changed))}.")
    else:
        lines.append(f"<b>fix changes none of the {n} links.</b>")
    rest = [f"keeps {len(kept)} as written (plausible)" if kept else "",
            f"leaves {others} untouched (nothing to compute from, or nothing wrong)"
            if others else ""]
    rest = [x for x in rest if x]
    if rest:
        lines.append("It " + " and ".join(rest) + ".")
    if left:
        lines.append(f'<span class="bad">It cannot compute {len(left)} that it should: '
                     f"{html.escape(_names(left))} (left as written; the table says why)."
                     "</span>")
    findings = [f for r in rows for f in r.findings] + list(data.robot_findings)
    counts = Counter(str(f.severity) for f in findings)
    lines.append("check: " + ", ".join(f"{counts.get(s, 0)} {s}{'s' if s != 'info' else ''}"
                                        for s in ("error", "warning", "info")) + ".")
    return '<div class="verdict">' + "".join(f"<p>{x}</p>" for x in lines) + "</div>"


#: compare's medians in the report's words: key, label, how to print.
MEDIANS = (("mass_ratio", "mass ratio", lambda x: f"×{x:.3g}"),
           ("com_distance", "CoM distance", lambda x: f"{x * 1000:.3g} mm"),
           ("com_distance_rel", "CoM distance ÷ link size", percent),
           ("inertia_rel_error", "tensor difference", percent),
           ("axis_angle_deg", "principal axes turned", lambda x: f"{x:.2g}°"))


def _summary_html(data: ReportData) -> str:
    medians = data.summary.get("median", {})
    median = ", ".join(f"{label} {fmt(medians[key])}" for key, label, fmt in MEDIANS
                       if medians.get(key) is not None)
    items = [html.escape(x) for x in (
        "written inertials against the geometry (uniform density), median over "
        f"{data.summary.get('links', len(data.rows))} links: {median or 'none'}",
        *data.scene.notes)]
    items += [finding_html(f, folded=False) for f in data.robot_findings]
    opts = data.options
    meta = html.escape(f"{data.fix.path} · geometry {opts.geometry}, mass {opts.mass}, "
                       f"density {opts.density:g} kg/m³"
                       f"{', spec' if opts.spec is not None else ''} · "
                       f"urdf-inertia {__version__}")
    return (f'<p class="meta">{meta}</p>{_verdict_html(data)}<ul class="meta">'
            + "".join(f"<li>{i}</li>" for i in items) + "</ul>")


def _swatch(color: str) -> str:
    return f'<span class="sw" style="background:{color}"></span>'


def _key_html() -> str:
    """What the 3-D view shows (its legend, below it, is the key and the toggle)."""
    return ('<p class="meta">Each box is the uniform box with the link\'s mass and '
            "principal moments, along the principal axes and centred at the CoM. The links "
            "fix changes are tinted and named, with their inertial as written and what fix "
            "writes; the links it keeps show their inertial as written. Click a legend "
            "entry to show or hide a group; drag to rotate, scroll to zoom.</p>")


def _link_list(data: ReportData) -> str:
    """Every link beside the 3-D view, in the report's order, with what fix does."""
    palette = {"changed": COLORS["existing"], "left": COLORS["left"],
               "kept": COLORS["kept"], "untouched": COLORS["untouched"]}
    items = [f"<li>{_swatch(palette[group(r.fix)])}<b>{html.escape(r.name)}</b> "
             f"{html.escape(STATUS_WORDS.get(r.fix.status, str(r.fix.status)))}</li>"
             for r in ranked(data.rows)]
    return f'<aside id="linklist"><h3>Links</h3><ol>{"".join(items)}</ol></aside>'


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
    panels = error_figures(data.error_series, data) if data.error_series["links"] else []
    titles = dict((key, title) for key, title, _, _ in ERROR_PANELS)
    for n, (_, fig) in enumerate(panels, start=1):
        figures[f"errors-{n}"] = fig
    plots = "".join(f"<div><h3>{html.escape(titles[key])}</h3>"
                    f"{_plot_div(f'errors-{n}', fig)}</div>"
                    for n, (key, fig) in enumerate(panels, start=1))
    drawn = {key for key, _ in panels}
    skipped = [title for key, title, _, _ in ERROR_PANELS if key not in drawn]
    note = (f'<p class="meta">Not drawn: {html.escape(", ".join(skipped))}, the same for '
            "every link.</p>" if panels and skipped else "")
    parts = [
        "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>urdf-inertia report: {name}</title><style>{_CSS}</style></head>",
        f'<body data-figures="{len(figures)}"><h1>Inertia report: {name}</h1>',
        _summary_html(data),
        "<h2>3-D view at the zero configuration</h2>", _key_html(),
        f'<div class="view">{_plot_div("view3d", figures["view3d"])}{_link_list(data)}'
        "</div>",
        f'<p class="meta">{len(data.scene.meshes)} elements drawn, '
        f"{data.scene.face_count} faces (meshes decimated for display only; the numbers "
        "use the full meshes).</p>",
        "<h2>Written inertials against the geometry</h2>",
        '<p class="meta">compare\'s numbers, links in the order of the table below. Bars are '
        f"coloured by what fix does:{_swatch(COLORS['existing'])}changed"
        f"{_swatch(COLORS['kept'])}kept as written (fix trusts a plausible written "
        "value: the CAD knows the materials, the geometry assumes one density)"
        f"{_swatch(COLORS['untouched'])}untouched. Dashed: compare's tolerance.</p>",
        f'<div class="panels" id="errors">{plots}</div>{note}' if panels else
        '<p class="meta">No link has both an inertial as written and geometry.</p>',
        "<h2>What fix does, link by link</h2>",
        '<p class="meta"><span class="e">as written</span> the inertial in the file, '
        '<span class="r">fix writes</span> what fix puts in its place; inertia about the '
        "CoM along the link frame's axes. Click a finding or a note count to read it.</p>",
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
