"""A copy of a URDF that an engine can load from a temporary folder, meshes resolved.

No engine understands every URI users write: MuJoCo ignores `package://` and strips
folders from mesh file names (`strippath` is on for URDF), PyBullet searches
`package://` relative to the working directory. The copy names each mesh by its absolute
path (resolved the way `fix` resolves it), turns MuJoCo's `strippath` off, and for
MuJoCo, which reads STL, OBJ and MSH only, converts other meshes (COLLADA, ...) to binary
STL with this package's reader. A geometry element whose mesh cannot be found is dropped:
`check`'s own findings report that mesh, and the engine still gets to load the rest.
Inertials are copied byte for byte (lxml keeps attribute text as written).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
from lxml import etree

from urdfinertia.descriptions.paths import resolve_mesh_path
from urdfinertia.descriptions.xml import parse_document
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.mesh.read.load import load_mesh

MUJOCO_MESHES = (".stl", ".obj", ".msh")
"""Mesh suffixes MuJoCo reads itself."""


def write_stl(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    """Binary STL of a triangle mesh (normals left zero: readers recompute them)."""
    tri = np.asarray(vertices, dtype=np.float32)[np.asarray(faces)]
    records = np.zeros(len(tri), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)),
                                        ("attr", "<u2")])
    records["v"] = tri
    with path.open("wb") as fh:
        fh.write(b"urdfinertia engine copy".ljust(80, b" "))
        fh.write(np.uint32(len(tri)).tobytes())
        fh.write(records.tobytes())


def prepare_urdf(data: bytes, path: Path, folder: Path, *, for_mujoco: bool,
                 package_dirs: Mapping[str, Path] | None = None) -> Path:
    """Write the engine copy of the URDF `data` (read from `path`) into `folder`."""
    root = parse_document(data, path, ("robot",))
    urdf_dir = path.parent
    converted: dict[Path, Path] = {}
    for mesh in list(root.iter("mesh")):
        geometry = mesh.getparent()
        element = geometry.getparent() if geometry is not None else None
        try:
            found = resolve_mesh_path(mesh.get("filename", ""), urdf_dir, package_dirs)
            if for_mujoco and found.suffix.lower() not in MUJOCO_MESHES:
                found = _as_stl(found, folder, converted)
        except UrdfInertiaError:
            if element is not None and element.getparent() is not None:
                element.getparent().remove(element)
            continue
        mesh.set("filename", str(found.resolve()))
    if for_mujoco:
        _compiler(root).set("strippath", "false")
    out = folder / "engine_copy.urdf"
    out.write_bytes(etree.tostring(root, xml_declaration=True, encoding="utf-8"))
    return out


def _as_stl(source: Path, folder: Path, converted: dict[Path, Path]) -> Path:
    if source not in converted:
        mesh = load_mesh(source)
        target = folder / f"mesh{len(converted)}_{source.stem}.stl"
        write_stl(target, mesh.vertices, mesh.faces)
        converted[source] = target
    return converted[source]


def _compiler(root: etree._Element) -> etree._Element:
    """The `<mujoco><compiler>` element MuJoCo reads from a URDF, created if absent."""
    mujoco = root.find("mujoco")
    if mujoco is None:
        mujoco = etree.SubElement(root, "mujoco")
    compiler = mujoco.find("compiler")
    if compiler is None:
        compiler = etree.SubElement(mujoco, "compiler")
    return compiler


def mujoco_compiler_options(data: bytes, path: Path) -> dict[str, str]:
    """The attributes of the URDF's own `<mujoco><compiler>`, as written."""
    root = parse_document(data, path, ("robot",))
    compiler = root.find("mujoco/compiler")
    return dict(compiler.attrib) if compiler is not None else {}
