"""Numbers of MJCF attributes: plain finite decimals, as the URDF reader takes them."""

from __future__ import annotations

import math

from urdfinertia.descriptions.urdf.read import _NUMBER, in_range
from urdfinertia.rules import Rule


class GeomError(ValueError):
    """One element's value cannot be used (the element is dropped, with this cause and
    its :class:`~urdfinertia.rules.Rule`: by default ``vector-unparseable``)."""

    def __init__(self, cause: str, rule: Rule = Rule.VECTOR_UNPARSEABLE) -> None:
        super().__init__(cause)
        self.rule = rule


def numbers(text: str, n: int, attr: str, *, finite: bool = True, at_least: int | None = None,
            ) -> tuple[float, ...]:
    """The numbers of `attr="text"`: exactly `n`, or `at_least`..`n` of them.

    `finite=False` lets `nan`/`inf` through (the linter reports them).
    """
    shown = text if len(text) <= 60 else text[:57] + "..."
    parts = text.split()
    low = n if at_least is None else at_least
    if not low <= len(parts) <= n:
        need = n if at_least is None else f"{low} to {n}"
        raise GeomError(f'{attr}="{shown}" needs {need} numbers')
    values = []
    for p in parts:
        if _NUMBER.match(p):
            values.append(float(p))
        elif not finite and p.lower().lstrip("+-") in ("nan", "inf", "infinity"):
            values.append(float(p))
        else:
            raise GeomError(f'{attr}="{shown}" is not a number')
    if finite and any(not math.isfinite(v) or not in_range(v) for v in values):
        raise GeomError(f'{attr}="{shown}" is out of range')
    return tuple(values)
