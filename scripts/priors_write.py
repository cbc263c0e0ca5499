"""What ``bench_priors.py --write`` and ``--fixture`` write: the data file the package
reads and the sample its tests refit."""

from __future__ import annotations

import datetime
import json
from collections import defaultdict
from pathlib import Path
from typing import Any

from priors_fit import MIN_ROBOT_LINKS
from priors_report import Result

from urdfinertia import __version__
from urdfinertia.priors.data import FORMAT, VERSION


def write_table(result: Result, path: Path, command: str, measured: dict[str, Any]) -> None:
    """The data file: the fit on every package, with what produced it (``measured``: the
    samples' header: the measuring command, its date and the corpus's versions)."""
    cells = {}
    for k, j in sorted(result.cells.items()):
        cell = dict(result.grid[j])
        cell["band"] = round(result.tensor_bands.get(k, result.tensor_bands["*"]), 4)
        cells[k] = cell
    doc = {
        "format": FORMAT, "version": VERSION,
        "produced": {"command": command, "urdfinertia": __version__,
                     "date": datetime.date.today().isoformat(),
                     "measured": measured,
                     "corpus": result.summary["packages"],
                     "held_out": "every figure is cross-validated by package (each package "
                                 "predicted by a model fitted on the others)",
                     "figures": {k: result.summary[k] for k in ("mass", "tensor")}},
        "mass": {"target": "log10 of the effective density, kg/m^3: the link's mass over "
                           "the volume of the geometry fix integrates with no inertial",
                 "coefficients": {k: round(v, 6) for k, v in
                                  sorted(result.mass.coefficients.items())},
                 "ridge": result.mass.ridge,
                 "weights": "1/sqrt(links of the package)",
                 "band": {"level": result.level, "low": round(result.band[0], 4),
                          "high": round(result.band[1], 4)},
                 "robot_band": {"level": result.robot_level,
                                "low": round(result.robot_band[0], 4),
                                "high": round(result.robot_band[1], 4),
                                "min_links": MIN_ROBOT_LINKS}},
        "structure": {"level": result.tensor_level, "cells": cells},
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(doc, indent=1) + "\n")


def write_fixture(result: Result, path: Path) -> None:
    """The test sample: every unique CAD link's package, target and terms (numeric values
    in :data:`~urdfinertia.priors.terms.NUMERIC` order, then the indices of its categories
    in ``categories``), with the other packages that hold the same link (``also_in``: a
    fold leaving one of them out does not fit on it)."""
    from urdfinertia.priors.terms import NUMERIC

    rows = result.corpus.rows
    where: dict[tuple[str, ...], set[str]] = defaultdict(set)
    for r in rows:
        where[r.key].add(r.package)
    categories = sorted({t for r in rows for t in r.terms if ":" in t})
    links = []
    for r in rows:
        if not r.unique:
            continue
        links.append([r.package, round(r.y, 6), [round(r.terms[t], 6) for t in NUMERIC],
                      [categories.index(t) for t in sorted(r.terms) if ":" in t],
                      sorted(where[r.key] - {r.package})])
    out = {"ridge": result.mass.ridge, "level": result.level, "numeric": list(NUMERIC),
           "categories": categories,
           "columns": ["package", "y", "numeric", "categories", "also_in"], "links": links}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, separators=(",", ":")) + "\n")
