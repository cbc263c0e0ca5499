"""Links of two descriptions of one robot matched by name, as converters rename them.

A converter keeps a link's name where its format allows it and rewrites it where not:
USD prim names must be identifiers (``link_3.0`` becomes ``link_3_0``, ``link-1``
``link_1``, a leading digit gains an underscore), some tools prefix the robot's or the
model's name (``panda_link0``, ``robot/link0``) or write the path of the prim. Names are
matched in rounds, each only between names left unmatched and only where the match is
one to one:

1. the same name;
2. the same identifier (every character but letters, digits and ``_`` made ``_``);
3. the same key: the identifier's last path component, lower case, with the longest
   prefix every name of its side shares removed (``robot_``, ``World_robot_``).

What is left unmatched on either side is listed, never dropped: a comparison that matched
1 of 41 links says so instead of reporting no differences.
"""

from __future__ import annotations

import os
import re
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass


@dataclass(frozen=True)
class Matching:
    """Pairs of names (A's, B's) in A's order, and the names of each side left over."""

    pairs: tuple[tuple[str, str], ...]
    only_a: tuple[str, ...]
    only_b: tuple[str, ...]

    @property
    def renamed(self) -> tuple[tuple[str, str], ...]:
        """The pairs whose names differ."""
        return tuple((a, b) for a, b in self.pairs if a != b)

    def summary(self) -> str:
        """``"41 of 41 links matched (40 renamed)"``, with what is left over named."""
        total = len(self.pairs) + len(self.only_a)
        text = f"{len(self.pairs)} of {total} links matched"
        if self.renamed:
            text += f" ({len(self.renamed)} renamed, as {_example(self.renamed)})"
        if self.only_a:
            text += f"; only in A: {_names(self.only_a)}"
        if self.only_b:
            text += f"; only in B: {_names(self.only_b)}"
        return text


def identifier(name: str) -> str:
    """``name`` as a valid identifier (what USD prim names must be)."""
    out = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return "_" + out if not out or out[0].isdigit() else out


def _last(name: str) -> str:
    return re.split(r"[/:]", name.rstrip("/:"))[-1] or name


def _keys(names: Sequence[str]) -> dict[str, str]:
    """Each name's key (round 3 of the module doc)."""
    tails = {n: identifier(_last(n)).lower() for n in names}
    prefix = os.path.commonprefix(list(tails.values())) if len(tails) > 1 else ""
    # only a prefix ending at a word boundary, and never a whole name
    cut = prefix.rfind("_") + 1 if prefix else 0
    if any(len(t) <= cut for t in tails.values()):
        cut = 0
    return {n: t[cut:].strip("_") or t for n, t in tails.items()}


def match_names(a: Sequence[str], b: Sequence[str]) -> Matching:
    """Match the names of side A with those of side B (module doc)."""
    left, right = list(dict.fromkeys(a)), list(dict.fromkeys(b))
    found: dict[str, str] = {}
    keys_a, keys_b = _keys(left), _keys(right)
    rounds: list[Callable[[str], str]] = [lambda n: n, identifier]
    for key_of in rounds:
        _round(left, right, found, key_of, key_of)
    _round(left, right, found, keys_a.__getitem__, keys_b.__getitem__)
    used = set(found.values())
    return Matching(tuple((n, found[n]) for n in left if n in found),
                    tuple(n for n in left if n not in found),
                    tuple(n for n in right if n not in used))


def _round(left: list[str], right: list[str], found: dict[str, str],
           key_a: Callable[[str], str], key_b: Callable[[str], str]) -> None:
    used = set(found.values())
    open_a = [n for n in left if n not in found]
    open_b = [n for n in right if n not in used]
    count_a = Counter(key_a(n) for n in open_a)
    by_key = {}
    count_b: Counter[str] = Counter()
    for n in open_b:
        k = key_b(n)
        count_b[k] += 1
        by_key[k] = n
    for n in open_a:
        k = key_a(n)
        if count_a[k] == 1 and count_b[k] == 1:
            found[n] = by_key[k]


def _names(names: Sequence[str], most: int = 5) -> str:
    shown = ", ".join(names[:most])
    return shown + (f" and {len(names) - most} more" if len(names) > most else "")


def _example(pairs: Sequence[tuple[str, str]]) -> str:
    a, b = pairs[0]
    return f"{a} -> {b}"
