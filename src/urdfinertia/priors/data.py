"""The priors' data file: fitted coefficients and calibration, read once per process.

``urdfinertia/data/priors.json`` is written by ``scripts/bench_priors.py --write`` and
records what produced it (``produced``: the command, the corpus by package, the package
version and the date). The code holds no fitted number: everything the model uses is
read from this file.
"""

from __future__ import annotations

import functools
import json
from dataclasses import dataclass
from importlib import resources
from typing import Any

#: the file's ``format`` and the ``version`` this code reads
FORMAT = "urdfinertia-priors"
VERSION = 1


class PriorsDataError(ValueError):
    """The data file is missing, unreadable or of another format or version."""


@dataclass(frozen=True)
class PriorTable:
    """The data file's content.

    mass : the density model (``coefficients`` by term of `urdfinertia.priors.terms`,
        ``band`` and ``robot_band``: quantiles of the held-out log10 ratio CAD/predicted).
    structure : the structure prior of tensors (``cells`` by key, ``level``).
    produced : what produced the file (command, corpus, version, date).
    """

    mass: dict[str, Any]
    structure: dict[str, Any]
    produced: dict[str, Any]

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> PriorTable:
        if doc.get("format") != FORMAT or doc.get("version") != VERSION:
            raise PriorsDataError(f"not a {FORMAT} file of version {VERSION}: "
                                  f"{doc.get('format')!r} version {doc.get('version')!r}")
        try:
            mass, structure = doc["mass"], doc["structure"]
            mass["coefficients"], mass["band"], mass["robot_band"]  # noqa: B018
            structure["cells"], structure["level"]  # noqa: B018
        except (KeyError, TypeError) as exc:
            raise PriorsDataError(f"priors data lacks {exc}") from None
        return cls(mass, structure, dict(doc.get("produced", {})))

    def as_dict(self) -> dict[str, Any]:
        return {"format": FORMAT, "version": VERSION, "produced": self.produced,
                "mass": self.mass, "structure": self.structure}


def data_text() -> str:
    """The packaged data file's text."""
    try:
        return (resources.files("urdfinertia") / "data" / "priors.json").read_text("utf-8")
    except OSError as exc:
        raise PriorsDataError(f"the priors data file cannot be read: {exc}") from None


@functools.lru_cache(maxsize=1)
def load_table() -> PriorTable:
    """The packaged table (read and checked once per process)."""
    try:
        doc = json.loads(data_text())
    except json.JSONDecodeError as exc:
        raise PriorsDataError(f"the priors data file is not JSON: {exc}") from None
    return PriorTable.from_dict(doc)
