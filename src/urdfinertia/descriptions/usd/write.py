"""Corrected MassAPI opinions as USD: an override layer over the asset, or the asset's
own root layer.

The override layer (`robot.inertia.usda` by default) sublayers the asset's root layer and
holds only `over` prims with `physics:mass`, `physics:centerOfMass`,
`physics:diagonalInertia` and `physics:principalAxes` (and `newton:inertia` where the
body has `NewtonMassAPI`, so Newton and the other engines agree). Its own opinions are
the strongest local ones, so they win over the asset's layers and payloads; the asset is
not touched, and dropping the layer undoes the fix. It repeats the root layer's stage
metadata (`defaultPrim`, `metersPerUnit`, `kilogramsPerUnit`, `upAxis`) because a
stage takes those from its root layer only.

`template` is the format's "expanded document": the override layer with no
opinions yet, carrying in its `customLayerData` what `patch` needs (the prim path
of each link, the bodies with `NewtonMassAPI`, the units); `patch` fills it. The
record stays: it says which prim each link of the reports is.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from urdfinertia.descriptions.formats import NewInertials, new_inertial
from urdfinertia.descriptions.usd.frames import matrix_quat
from urdfinertia.errors import UrdfError

_KEY = "urdfinertia"
_STAGE_METADATA = ("defaultPrim", "metersPerUnit", "kilogramsPerUnit", "upAxis")


def override_path(path: Path) -> Path:
    """Where `fix` writes the override layer of an asset: `robot.inertia.usda`."""
    return path.with_name(f"{path.stem}.inertia.usda")


def template(path: Path, prim_paths: Mapping[str, str], newton: frozenset[str],
             mpu: float, kpu: float, instances: tuple[str, ...] = ()) -> bytes:
    """The override layer of `path` without opinions (its sublayer relative to it)."""
    from pxr import Sdf, Vt

    root = Sdf.Layer.FindOrOpen(str(path))
    layer = Sdf.Layer.CreateAnonymous(".usda")
    for key in _STAGE_METADATA:
        if root is not None and root.pseudoRoot.HasInfo(key):
            layer.pseudoRoot.SetInfo(key, root.pseudoRoot.GetInfo(key))
    layer.subLayerPaths.append(f"./{path.name}")
    layer.comment = (f"Mass properties by urdf-inertia over {path.name}, which is not "
                     "changed; remove this layer to undo")
    names = list(prim_paths)
    layer.customLayerData = {_KEY: {
        "links": Vt.StringArray(names),
        "paths": Vt.StringArray([prim_paths[n] for n in names]),
        "newton": Vt.StringArray(sorted(newton)),
        "instances": Vt.StringArray(list(instances)), "metersPerUnit": float(mpu),
        "kilogramsPerUnit": float(kpu)}}
    return layer.ExportToString().encode()


def _open(data: bytes) -> Any:
    from pxr import Sdf

    layer = Sdf.Layer.CreateAnonymous(".usda")
    if not layer.ImportFromString(data.decode("utf-8")):
        raise UrdfError("the USD override layer cannot be read back")
    return layer


def patch(data: bytes, new: NewInertials) -> bytes:
    """The override layer `data` (from `template`) with the new mass properties."""
    layer = _open(data)
    record = dict(layer.customLayerData).get(_KEY)
    if record is None:
        raise UrdfError("not an override layer made by urdf-inertia")
    if not new:
        return data  # nothing recomputed: the layer is unchanged (``changed`` is False)
    author(layer, new, record)
    return layer.ExportToString().encode()


def author(layer: Any, new: NewInertials,
           record: Mapping[str, Any]) -> None:
    """Author `new` into `layer` at the links' prims (`over` where it has none)."""
    from pxr import Gf, Sdf, Vt

    paths = dict(zip(record["links"], record["paths"], strict=True))
    newton = set(record["newton"])
    mpu, kpu = float(record["metersPerUnit"]), float(record["kilogramsPerUnit"])
    targets = [Sdf.Path(paths[name]) for name in new]
    for instance in record.get("instances", ()):  # opinions below an instance are ignored
        where = Sdf.Path(instance)
        if any(t.HasPrefix(where) for t in targets):
            Sdf.CreatePrimInLayer(layer, where).SetInfo("instanceable", False)
    for name, value in new.items():
        mp, size = new_inertial(value).props, new_inertial(value).size
        spec = Sdf.CreatePrimInLayer(layer, Sdf.Path(paths[name]))
        schemas = ["PhysicsMassAPI"] + (["NewtonMassAPI"] if name in newton else [])
        _apply(spec, schemas)
        inertia = np.asarray(mp.inertia, dtype=np.float64) / (kpu * mpu * mpu)
        inertia = np.where(np.abs(inertia) < 1e-12 * max(np.abs(inertia).max(), 1e-300),
                           0.0, inertia)
        diagonal, rot = principal(inertia)
        com = np.asarray(mp.com, dtype=np.float64) / mpu
        if size > 0:
            com = np.where(np.abs(com) < 1e-12 * size / mpu, 0.0, com)
        _set(spec, "physics:mass", Sdf.ValueTypeNames.Float, float(mp.mass) / kpu)
        _set(spec, "physics:centerOfMass", Sdf.ValueTypeNames.Point3f, Gf.Vec3f(*com))
        _set(spec, "physics:diagonalInertia", Sdf.ValueTypeNames.Float3,
             Gf.Vec3f(*diagonal))
        w, x, y, z = matrix_quat(rot)
        _set(spec, "physics:principalAxes", Sdf.ValueTypeNames.Quatf, Gf.Quatf(w, x, y, z))
        if name in newton:
            t = inertia
            _set(spec, "newton:inertia", Sdf.ValueTypeNames.DoubleArray, Vt.DoubleArray(
                [t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]]))


def principal(tensor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments and a proper rotation R (columns: axes), `T = R diag R^T`."""
    moments, axes = np.linalg.eigh(0.5 * (tensor + tensor.T))
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
    return moments, axes


def _apply(spec: Any, schemas: list[str]) -> None:
    from pxr import Sdf

    current = spec.GetInfo("apiSchemas") if spec.HasInfo("apiSchemas") else None
    items = list(current.prependedItems) if current is not None else []
    present = set(items)
    if current is not None:
        present |= set(current.explicitItems) | set(current.appendedItems)
    missing = [s for s in schemas if s not in present]
    if not missing:
        return
    op = Sdf.TokenListOp()
    if current is not None and current.isExplicit:
        op.explicitItems = list(current.explicitItems) + missing
    else:
        op.prependedItems = items + missing
        if current is not None:
            op.appendedItems = list(current.appendedItems)
            op.deletedItems = [d for d in current.deletedItems if d not in missing]
    spec.SetInfo("apiSchemas", op)


def _set(spec: Any, name: str, type_name: Any, value: Any) -> None:
    from pxr import Sdf

    attr = spec.attributes.get(name) if name in spec.attributes else None
    if attr is None:
        attr = Sdf.AttributeSpec(spec, name, type_name)
    attr.default = value


def relocate(data: bytes, source: Path, output: Path) -> tuple[bytes, int]:
    """The override layer's sublayer path made to resolve from `output`'s folder."""
    layer = _open(data)
    paths = list(layer.subLayerPaths)
    moved = [os.path.relpath(source / p, output) if not os.path.isabs(p) else p
             for p in paths]
    moved = [m if os.path.isabs(m) or m.startswith(".") else f"./{m}" for m in moved]
    if moved == paths:
        return data, 0
    del layer.subLayerPaths[:]
    for m in moved:
        layer.subLayerPaths.append(m.replace(os.sep, "/"))
    return layer.ExportToString().encode(), sum(a != b for a, b in zip(paths, moved,
                                                                       strict=True))


def in_place(path: Path, override: bytes) -> None:
    """Author the override layer's opinions into the asset's root layer at `path`
    (written atomically, in its own format; the original kept as `path.bak`)."""
    import shutil

    from pxr import Sdf, UsdUtils

    if path.suffix.lower() == ".usdz":
        raise UrdfError("--in-place cannot author into a .usdz package (read-only "
                        "zip); use the override layer (the default)", file=path)
    root = Sdf.Layer.FindOrOpen(str(path))
    if root is None:
        raise UrdfError("USD cannot read this layer", file=path)
    strong = _open(override)
    del strong.subLayerPaths[:]
    for key in _STAGE_METADATA:  # the root's own metadata stays as it is
        if strong.pseudoRoot.HasInfo(key):
            strong.pseudoRoot.ClearInfo(key)
    strong.comment = ""
    custom = dict(strong.customLayerData)
    custom.pop(_KEY, None)
    strong.customLayerData = custom
    UsdUtils.StitchLayers(strong, root)
    tmp = path.with_name(f".{path.stem}.urdfinertia-tmp{path.suffix}")
    try:
        if not strong.Export(str(tmp), args={"format": _format_of(path)}
                             if path.suffix.lower() == ".usd" else {}):
            raise UrdfError("cannot write the root layer", file=path)
        shutil.copy2(path, path.with_name(path.name + ".bak"))
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    root.Reload(force=True)


def _format_of(path: Path) -> str:
    with path.open("rb") as fh:
        return "usdc" if fh.read(8) == b"PXR-USDC" else "usda"
