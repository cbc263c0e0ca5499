"""Copies and mirror twins: inertials that say what the author meant by comparing links.

- A *copy* (:data:`RULES` "inertial-copied"): a link whose inertial equals another link's,
  byte for byte or within round-off, while their geometries differ. The copy is the link
  whose geometry the inertial fits worse (the score of :mod:`urdfinertia.inertia.slips`);
  it is named with the link it was copied from.
- *Mirror twins* ("twins-disagree"): links whose names pair left and right (``left_`` /
  ``right_``, ``_l`` / ``_r``, ``L`` / ``R`` ...) and whose geometries mirror each other
  (same volume and box extents), with masses, CoM offsets or principal moments that differ
  beyond the mirror map (which keeps all three). The finding is on the side that agrees
  worse with its geometry, and says which side agrees.

The judgement (:mod:`.robot`) acts on a copy: the copy's values are derived from its own
geometry at the density of the link it was copied from. Twins that disagree are only said:
which side is right is the author's call, unless one is ten times the other's mass
(:mod:`.robot`'s mass distribution).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.findings import Finding
from urdfinertia.inertia.slips import (
    Scored,
    Solid,
    Written,
    no_edit,
    placeholder_shaped,
    score_edit,
)
from urdfinertia.judge.slips import LIMITS, written_of
from urdfinertia.rules import Rule

#: Two inertials within this relative difference (every value) are the same (round-off).
SAME_RTOL = 1e-6
#: Geometries whose volume or a box extent differ by more than this fraction differ.
GEOMETRY_DIFFERS = 0.3
#: A copy fits its own geometry worse than the source fits its own by at least this much
#: (the score of :mod:`urdfinertia.inertia.slips`, chi-square units).
COPY_MARGIN = 9.0
#: Masses below this (kg) are frames and sensors, whose shared token inertials are no copy.
COPY_MIN_MASS = 1e-3
#: Mirror twins' geometries agree to this fraction (volume and sorted box extents).
MIRROR_AGREES = 0.05
#: Twins disagree when their masses differ by more than this fraction ...
TWIN_MASS = 0.05
#: ... or a principal moment by more than this fraction ...
TWIN_MOMENTS = 0.2
#: ... or their CoMs' distances from their centroids by more than this many box diagonals.
TWIN_COM = 0.1
#: Scores within this many chi-square units say neither side agrees better.
CLEARLY = 2.0

_SIDES = (("left", "right"), ("Left", "Right"), ("LEFT", "RIGHT"), ("l", "r"), ("L", "R"),
          ("lf", "rf"), ("lh", "rh"), ("LF", "RF"), ("LH", "RH"))
_SWAP = {a: b for pair in _SIDES for a, b in (pair, pair[::-1])}
_TOKENS = re.compile(r"([A-Za-z]+|[^A-Za-z]+)")


@dataclass(eq=False)
class _Body:
    link: Link
    raw: RawInertial
    written: Written
    #: the geometry's solid, read when first asked for (most links are in no pair)
    read: Callable[[Link], Solid | None]
    #: the solid of each of the link's geometry roles ("collision", "visual", "geom"), read
    #: when first asked for: a copy is told by geometry that differs in every role
    roles: Callable[[Link], dict[str, Solid]] | None = None
    _solid: Solid | None = None
    _done: bool = False
    _scored: Scored | None = None
    _roles: dict[str, Solid] | None = None

    def role_solids(self) -> dict[str, Solid]:
        if self._roles is None:
            self._roles = self.roles(self.link) if self.roles is not None else (
                {"body": self.solid} if self.solid is not None else {})
        return self._roles

    def fit_in(self, solid: Solid) -> float:
        """The written inertial's score against ``solid`` (lower: agrees better)."""
        return score_edit(no_edit(self.written), solid, LIMITS).score

    @property
    def solid(self) -> Solid | None:
        if not self._done:
            self._solid, self._done = self.read(self.link), True
        return self._solid

    def fit(self) -> float:
        """The written inertial's score against its own geometry (lower: agrees better)."""
        if self.solid is None:
            return float("inf")
        return self.scored().score

    def feasible(self) -> bool:
        """The written inertial is valid and plausible against its own geometry."""
        return self.solid is not None and self.scored().feasible

    def scored(self) -> Scored:
        assert self.solid is not None
        if self._scored is None:
            self._scored = score_edit(no_edit(self.written), self.solid, LIMITS)
        return self._scored


def twin_names(name: str) -> list[str]:
    """Names of ``name``'s other side: one left/right token swapped ("left_hip" ->
    "right_hip", "hip_l" -> "hip_r", "LHipPitch" -> "RHipPitch")."""
    parts = _TOKENS.findall(name)
    out = []
    for i, tok in enumerate(parts):
        if tok in _SWAP:
            out.append("".join([*parts[:i], _SWAP[tok], *parts[i + 1:]]))
        for side in ("L", "R", "l", "r"):  # a leading capital side: "LHip" -> "RHip"
            if tok.startswith(side) and len(tok) > 1 and tok[1].isupper():
                other = {"L": "R", "R": "L", "l": "r", "r": "l"}[side]
                out.append("".join([*parts[:i], other + tok[1:], *parts[i + 1:]]))
        for word in ("left", "right", "Left", "Right"):  # "leftarm" -> "rightarm"
            if tok.startswith(word) and tok != word:
                other = _SWAP[word]
                out.append("".join([*parts[:i], other + tok[len(word):], *parts[i + 1:]]))
    return [n for n in dict.fromkeys(out) if n != name]


def bodies_of(robot: Robot, solid_of: Callable[[Link], Solid | None],
              roles_of: Callable[[Link], dict[str, Solid]] | None = None,
              ) -> dict[str, _Body]:
    """The links with a finite written inertial, each with its solid (and the solid of
    each of its geometry roles) read on demand."""
    bodies: dict[str, _Body] = {}
    for link in robot.links:
        w = written_of(link)
        if w is None or link.inertial is None:
            continue
        with np.errstate(all="ignore"):
            raw = RawInertial.from_inertial(link.inertial)
            if not (raw.mass_ok and raw.com_ok) or not np.all(np.isfinite(w.entries)) \
                    or not np.all(np.isfinite(raw.inertia)):
                continue
        bodies[link.name] = _Body(link, raw, w, solid_of, roles_of)
    return bodies


def copy_findings(bodies: dict[str, _Body]) -> list[tuple[Finding, str]]:
    """Copies (module doc): each finding with the name of the link copied from."""
    return _copies(bodies)


def twin_findings(bodies: dict[str, _Body]) -> list[Finding]:
    """Mirror twins that disagree (module doc), in link order."""
    return _twins(bodies)


def _values(b: _Body) -> np.ndarray:
    w = b.written
    return np.concatenate(([w.mass], w.xyz, w.rpy, w.entries))


def _same(a: _Body, b: _Body) -> str | None:
    """"byte for byte", "within round-off" or None."""
    va, vb = _values(a), _values(b)
    if np.array_equal(va, vb):
        return "byte for byte"
    if np.all(np.abs(va - vb) <= SAME_RTOL * np.maximum(np.abs(va), np.abs(vb))):
        return "within round-off"
    return None


def _signature(s: Solid) -> np.ndarray:
    return np.concatenate(([s.volume], np.sort(np.asarray(s.hi) - np.asarray(s.lo))))


def _differ(a: Solid, b: Solid, tol: float) -> bool:
    sa, sb = _signature(a), _signature(b)
    return bool(np.any(np.abs(sa - sb) > tol * np.maximum(np.abs(sa), np.abs(sb))))


def _copyable(b: _Body) -> bool:
    """An inertial worth tracing: a real mass, not a typed placeholder (equal diagonal:
    1e-8 on every camera frame is shared, not copied)."""
    return b.raw.mass >= COPY_MIN_MASS and not placeholder_shaped(b.written)


def _copies(bodies: dict[str, _Body]) -> list[tuple[Finding, str]]:
    out = []
    names = [n for n, b in bodies.items() if _copyable(b)]
    done: set[str] = set()
    for i, name in enumerate(names):
        if name in done:
            continue
        group = [name] + [n for n in names[i + 1:] if n not in done
                          and _same(bodies[name], bodies[n]) is not None]
        done.update(group)
        with_geometry = [n for n in group if bodies[n].solid is not None]
        if len(with_geometry) < 2:
            continue
        fits = {n: bodies[n].fit() for n in with_geometry}
        source = min(with_geometry, key=lambda n: fits[n])
        src = bodies[source]
        assert src.solid is not None
        if not src.feasible():
            continue  # the inertial fits no geometry of the group: nothing says which
        for n in with_geometry:
            b = bodies[n]
            assert b.solid is not None
            if n == source or not _copied(b, src):
                continue
            how = _same(b, src)
            out.append((Finding(Rule.INERTIAL_COPIED, n, (
                f"inertial equals {source}'s ({how}) while their geometries differ "
                f"(volume {b.solid.volume:.3g} vs {src.solid.volume:.3g} m^3); it fits "
                f"{source}'s geometry better (score {fits[source]:.1f} vs {fits[n]:.1f}): "
                f"copied from {source}?"), b.link.inertial.line if b.link.inertial else None,
                "inertial"), source))
    return out


def _copied(b: _Body, src: _Body) -> bool:
    """``b``'s inertial, equal to ``src``'s, was copied from it: in every geometry role both
    links have, their geometries differ and ``b`` fits its own clearly worse than ``src``
    fits its own (front and rear legs sharing one CAD part share their geometry too, in
    one role at least: no copy)."""
    mine, theirs = b.role_solids(), src.role_solids()
    common = [r for r in mine if r in theirs]
    if not common:
        return False
    for role in common:
        if not _differ(mine[role], theirs[role], GEOMETRY_DIFFERS):
            return False
        if b.fit_in(mine[role]) - src.fit_in(theirs[role]) < COPY_MARGIN:
            return False
    return True


def _twins(bodies: dict[str, _Body]) -> list[Finding]:
    out = []
    seen: set[frozenset[str]] = set()
    for name, a in bodies.items():
        for other in twin_names(name):
            b = bodies.get(other)
            pair = frozenset((name, other))
            if b is None or pair in seen:
                continue
            seen.add(pair)
            if a.solid is None or b.solid is None or _differ(a.solid, b.solid, MIRROR_AGREES):
                continue
            if _disagreement(a, b):
                out.append(_twin_finding(a, b))
    return out


def _disagreement(a: _Body, b: _Body) -> str:
    """How ``a`` differs from its twin ``b`` beyond the mirror map ("" when it does not)."""
    assert a.solid is not None and b.solid is not None
    why = []
    if abs(a.raw.mass - b.raw.mass) > TWIN_MASS * max(a.raw.mass, b.raw.mass):
        why.append(f"mass {a.raw.mass:.4g} kg against {b.raw.mass:.4g}")
    ma = np.linalg.eigvalsh(a.raw.inertia)
    mb = np.linalg.eigvalsh(b.raw.inertia)
    rel = float(np.max(np.abs(ma - mb) / np.maximum(np.maximum(np.abs(ma), np.abs(mb)),
                                                     1e-300)))
    if rel > TWIN_MOMENTS:
        why.append(f"principal moments differ by up to {100 * rel:.0f} %")
    da = float(np.linalg.norm(a.raw.com - a.solid.centroid))
    db = float(np.linalg.norm(b.raw.com - b.solid.centroid))
    diag = max(a.solid.diagonal, b.solid.diagonal)
    if abs(da - db) > TWIN_COM * diag:
        why.append(f"CoM {da:.3g} m from the geometry's centroid against {db:.3g}")
    return "; ".join(why)


def _twin_finding(a: _Body, b: _Body) -> Finding:
    fa, fb = a.fit(), b.fit()
    if abs(fa - fb) < CLEARLY:
        worse, better, verdict = a, b, "neither side agrees clearly better with its geometry"
    else:
        worse, better = (a, b) if fa > fb else (b, a)
        verdict = (f"{better.link.name}'s agrees with the geometry (score "
                   f"{min(fa, fb):.1f} against {max(fa, fb):.1f})")
    why = _disagreement(worse, better)
    return Finding(Rule.TWINS_DISAGREE, worse.link.name, (
        f"mirror twin of {better.link.name} with the same geometry, but {why} there: "
        f"{verdict}"), worse.link.inertial.line if worse.link.inertial else None)
