"""Identical inputs, identical verdicts, over real robots: a link whose inertial and
geometry are the same in two files of one robot package gets the same verdict in both,
and mirror twins whose inertials are mirror images get the same action. Over every
example-robot-data package with more than one description (and a corpus of
``scripts/changed_links.py``'s manifest layout when ``URDFINERTIA_DEV_CORPUS`` names it)."""

from __future__ import annotations

import os
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest
from support.corpus import example_robot_data_dir

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.formats import read_description
from urdfinertia.judge.twins import twin_names
from urdfinertia.plan.fix import verdicts

pytestmark = pytest.mark.corpus


def _packages() -> dict[str, list[Path]]:
    root = example_robot_data_dir()
    if root is None:
        return {}
    out: dict[str, list[Path]] = defaultdict(list)
    for path in sorted((root / "robots").rglob("*.urdf")):
        out[path.relative_to(root / "robots").parts[0]].append(path)
    return {k: v for k, v in out.items() if len(v) > 1}


PACKAGES = _packages()


def _shape(ref, folder: Path) -> tuple:  # noqa: ANN001
    shape = ref.shape
    fields = tuple(sorted(vars(shape).items()))
    if hasattr(shape, "filename"):  # a mesh: the file it names, wherever it is named from
        name = str(shape.filename)
        if not name.startswith(("package:", "model:", "file:")):
            name = str((folder / name).resolve())
        fields = tuple((k, name if k == "filename" else v) for k, v in fields)
    return (type(shape).__name__, fields, ref.origin.xyz, ref.origin.rpy)


def _key(link, folder: Path, moves: str) -> tuple | None:  # noqa: ANN001
    """The link's inputs: its inertial, its geometry and where it hangs (`_moves`)."""
    i = link.inertial
    if i is None:
        return None
    values = (i.mass, i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz, i.origin.xyz, i.origin.rpy)
    geometry = tuple(sorted(("c", _shape(r, folder)) for r in link.collisions)) + tuple(
        sorted(("v", _shape(r, folder)) for r in link.visuals))
    return values, geometry, moves


def _moves(robot, name: str) -> str:  # noqa: ANN001
    """Where the link hangs: "root", "moves" (a joint moves it) or "fixed"."""
    parent = [j for j in robot.joints if j.child == name]
    if not parent:
        return "root"
    return "moves" if parent[0].type != "fixed" else "fixed"


def _verdict(r) -> tuple:  # noqa: ANN001
    """The action, its reason and, where the written mass is kept, the values written (a
    mass the prior gives depends on the link's place in the chain, not only its inputs)."""
    after = r.after
    values = None if after is None or "mass" not in r.kept else tuple(np.round(
        [after.mass, *after.com, *after.inertia.ravel()], 9))
    return r.action, r.why, values


def _compare(robot, found, path, label, seen, clashes) -> None:  # noqa: ANN001
    """Record each link's verdict under its key; a clash with a link seen before of the
    same key, and between mirror twins, is appended to ``clashes``."""
    for link in robot.links:
        key = _key(link, path.parent, _moves(robot, link.name))
        if key is None:
            continue
        v = _verdict(found[link.name])
        where = f"{label}:{link.name}"
        if key in seen and seen[key][1] != v:
            clashes.append(f"{seen[key][0]} {seen[key][1][0]} vs {where} {v[0]}")
        seen.setdefault(key, (where, v))
    _twins(robot, found, clashes, label)


@pytest.mark.skipif(not PACKAGES, reason="example-robot-data is not installed")
@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_identical_links_in_one_robots_files_get_one_verdict(package):
    meshes = MeshLibrary()
    seen: dict[tuple, tuple[str, tuple]] = {}
    clashes = []
    for path in PACKAGES[package]:
        try:
            robot, _ = read_description(path)
        except Exception:  # noqa: BLE001 - a file the reader refuses has no verdicts
            continue
        found = {r.name: r for r in verdicts(robot, FixOptions(), meshes).links}
        _compare(robot, found, path, path.name, seen, clashes)
    assert not clashes, "\n".join(clashes[:20])


#: Reflections of a link frame: (CoM sign flips, products that change sign).
MIRRORS = {"xz": ((1, -1, 1), ("ixy", "iyz")), "yz": ((-1, 1, 1), ("ixy", "ixz")),
           "xy": ((1, 1, -1), ("ixz", "iyz"))}


def _mirrored(a, b) -> bool:  # noqa: ANN001
    """Inertial ``b`` is ``a`` reflected through a plane of the link frame (what a mirror
    twin's is when its geometry is the mirror image too)."""
    if a.mass != b.mass or a.origin.rpy != b.origin.rpy:
        return False
    for flips, products in MIRRORS.values():
        com = tuple(s * x for s, x in zip(flips, a.origin.xyz, strict=True))
        if not np.allclose(com, b.origin.xyz, rtol=1e-9, atol=1e-12):
            continue
        ok = all(np.isclose((-1 if k in products else 1) * getattr(a, k), getattr(b, k),
                            rtol=1e-9, atol=1e-15)
                 for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))
        if ok:
            return True
    return False


def _twins(robot, found, clashes: list[str], file: str) -> None:  # noqa: ANN001
    """Mirror twins whose inertials are mirror images and whose geometry has one volume get
    one action. (Twins with one tensor copied unmirrored onto mirrored geometry are not
    identical inputs: one side fits its geometry and the other does not.)"""
    by_name = {lk.name: lk for lk in robot.links}
    for name, link in by_name.items():
        for other in twin_names(name):
            twin = by_name.get(other)
            if twin is None or other < name or link.inertial is None or twin.inertial is None:
                continue
            if not _mirrored(link.inertial, twin.inertial):
                continue
            ra, rb = found[name], found[other]
            va = ra.choice.diagonal if ra.choice is not None else None
            vb = rb.choice.diagonal if rb.choice is not None else None
            if va is not None and vb is not None and not np.isclose(va, vb, rtol=1e-3):
                continue  # mirrored values over geometry that is not mirrored
            if ra.action != rb.action:
                clashes.append(f"{file}: twins {name} {ra.action} vs {other} {rb.action}")


@pytest.mark.skipif(not os.environ.get("URDFINERTIA_DEV_CORPUS"),
                    reason="set URDFINERTIA_DEV_CORPUS to a corpus folder with a manifest")
def test_identical_links_over_a_corpus():
    import json

    root = Path(os.environ["URDFINERTIA_DEV_CORPUS"])
    entries = json.loads((root / "manifest.json").read_text())
    by_package: dict[str, list[dict]] = defaultdict(list)
    for e in entries:
        by_package[e["package"]].append(e)
    from urdfinertia.descriptions.xacro.expand import settings_for

    clashes: list[str] = []
    for files in by_package.values():
        seen: dict[tuple, tuple[str, tuple]] = {}
        for e in files:
            dirs = {k: root / v for k, v in (e.get("package_dirs") or {}).items()}
            path = root / e["file"]
            try:
                with settings_for(e.get("xacro_args") or None, dirs):
                    robot, _ = read_description(path)
            except Exception:  # noqa: BLE001
                continue
            meshes = mesh_library(dirs)
            found = {r.name: r for r in verdicts(robot, FixOptions(package_dirs=dirs),
                                                  meshes).links}
            _compare(robot, found, path, e["file"], seen, clashes)
    assert not clashes, "\n".join(clashes[:30])
