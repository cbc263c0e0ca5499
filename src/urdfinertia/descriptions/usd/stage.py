"""Opening a USD asset: the optional `pxr` import, the composed stage, its units.

OpenUSD reports problems through its diagnostic delegate (and sometimes only there): a
corrupt layer, a reference or payload whose layer cannot be found. Opening a stage here
collects those diagnostics, names the layer each is about, and turns a stage that cannot
be read into one [`UrdfError`][urdfinertia.errors.UrdfError] (the CLI prints one line, exit 2).
Missing sublayers, references and payloads are named as problems of the document.
"""

from __future__ import annotations

import os
import re
import stat
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

from urdfinertia.errors import UrdfError

MISSING_PXR = (
    "reading USD needs OpenUSD's Python modules (pxr), which are not installed: "
    "pip install usd-core (or, beside urdf-usd-converter / mujoco-usd-converter, "
    "pip install usd-exchange; never both, and neither inside Isaac Sim, which has its own)"
)
"""What a user without `pxr` is told; `pxr` comes from one of several wheels that must not be
installed together (see the `usd` extra in the project's metadata).
"""

SUFFIXES = (".usd", ".usda", ".usdc", ".usdz")


def pxr() -> ModuleType:
    """The `pxr` package, or a `UrdfError` with the install command."""
    try:
        import pxr as module
        from pxr import Sdf, Usd, UsdGeom, UsdPhysics  # noqa: F401 - the modules used
    except ImportError as exc:
        if "initialization failed" in str(exc) or "pxr" not in str(exc):
            raise UrdfError(f"OpenUSD's pxr is installed but does not load ({exc}): two "
                            "providers (usd-core and usd-exchange) in one environment break "
                            "each other; uninstall one") from None
        raise UrdfError(MISSING_PXR) from None
    return module


@dataclass(frozen=True)
class Opened:
    """A composed stage and what opening it reported."""

    stage: Any  # pxr.Usd.Stage
    meters_per_unit: float
    kilograms_per_unit: float
    missing: tuple[str, ...]
    """Layers that a sublayer, reference or payload names but that cannot be opened."""


def open_stage(path: Path) -> Opened:
    """The composed stage of `path` with every payload loaded; refuses what USD cannot
    read with one line naming the layer."""
    px = pxr()
    from pxr import Sdf, Tf, Usd, UsdGeom, UsdPhysics

    if path.suffix.lower() not in SUFFIXES:
        raise UrdfError(f"not a USD file (suffix {path.suffix or 'none'}; expected one of "
                        f"{', '.join(SUFFIXES)})", file=path)
    if not path.is_file():
        raise UrdfError("no such file", file=path)
    del px
    with _Diagnostics(Tf) as diag:
        _check_layer_file(str(path), path, None)
        try:
            root = Sdf.Layer.FindOrOpen(str(path))
        except Tf.ErrorException as exc:
            raise UrdfError(f"USD cannot read this layer: {_first_line(exc)}",
                            file=path) from None
        if root is None:
            raise UrdfError(f"USD cannot read this layer{diag.cause()}", file=path)
        # every layer the stage will compose is checked before USD opens it, and kept
        # open (the registry hands these very layers to the composition)
        layers = _checked_layers(root, path)
        try:
            stage = Usd.Stage.Open(root, Usd.Stage.LoadAll)
        except Tf.ErrorException as exc:
            raise UrdfError(f"USD cannot compose the stage: {_first_line(exc)}",
                            file=path) from None
        if stage is None:
            raise UrdfError(f"USD cannot compose the stage{diag.cause()}", file=path)
        missing = _missing_layers(stage, path)
        del layers
    mpu = float(UsdGeom.GetStageMetersPerUnit(stage))
    kpu = float(UsdPhysics.GetStageKilogramsPerUnit(stage))
    if not (mpu > 0 and kpu > 0):
        raise UrdfError(f"stage units are not positive (metersPerUnit {mpu:g}, "
                        f"kilogramsPerUnit {kpu:g})", file=path)
    return Opened(stage, mpu, kpu, missing)


def _missing_layers(stage: Any, path: Path) -> tuple[str, ...]:
    """Asset paths named by the composition (sublayers, references, payloads) that do not
    resolve to a layer, each as `asset (named in layer)`."""
    from pxr import Sdf, Tf

    out: list[str] = []
    seen: set[str] = set()
    for layer in stage.GetUsedLayers():
        for ref in _external(layer):
            if ref in seen:
                continue
            seen.add(ref)
            resolved = layer.ComputeAbsolutePath(ref)
            try:
                found = Sdf.Layer.FindOrOpen(resolved)
            except Tf.ErrorException as exc:  # there, but not a layer USD can read
                out.append(f"{ref} (named in {_short(layer.realPath, path)}: "
                           f"{_first_line(exc)})")
                continue
            if found is None:
                out.append(f"{ref} (named in {_short(layer.realPath, path)})")
    return tuple(out)


def _external(layer: Any) -> list[str]:
    """The asset paths a layer's sublayers, references and payloads name."""
    refs = layer.GetExternalReferences() if hasattr(layer, "GetExternalReferences") \
        else layer.externalReferences
    return [ref for ref in refs if ref]


def _checked_layers(root: Any, path: Path) -> list[Any]:
    """Every layer reachable from ``root`` through sublayers, references and payloads,
    opened after :func:`_check_layer_file` (USD itself would block on a FIFO or read a
    device or a huge file to its end). A layer that does not exist or that USD cannot
    parse is left to the composition, which reports it (:func:`_missing_layers`)."""
    from pxr import Sdf, Tf

    opened = [root]
    seen = {str(root.realPath)}
    todo = [root]
    while todo:
        layer = todo.pop()
        for ref in _external(layer):
            resolved = layer.ComputeAbsolutePath(ref)
            if not resolved or resolved in seen:
                continue
            seen.add(resolved)
            if not _check_layer_file(resolved, path, (ref, layer)):
                continue
            try:
                found = Sdf.Layer.FindOrOpen(resolved)
            except Tf.ErrorException:
                continue
            if found is not None:
                opened.append(found)
                todo.append(found)
    return opened


def _check_layer_file(resolved: str, path: Path, named: tuple[str, Any] | None) -> bool:
    """Whether the layer file exists (False: the composition reports it missing);
    :class:`UrdfError` when it is not a regular file or larger than a description may be.

    Only the file part of a package path (``asset.usdz[inner.usda]``) is looked at.
    """
    from urdfinertia.descriptions.xml import MAX_DOCUMENT_BYTES

    file = resolved.split("[", 1)[0]
    where = "" if named is None else \
        f"layer @{named[0]}@ named in {_short(named[1].realPath, path)} "
    try:
        info = os.stat(file)
    except (OSError, ValueError):
        return False
    if not stat.S_ISREG(info.st_mode):
        raise UrdfError(f"{where or 'layer '}is not a regular file ({file}): a FIFO, "
                        "device or folder is not read", file=path)
    if info.st_size > MAX_DOCUMENT_BYTES:
        raise UrdfError(f"{where or 'layer '}is {info.st_size} bytes, more than the limit "
                        f"{MAX_DOCUMENT_BYTES} bytes of a description ({file})", file=path)
    return True


def _short(real: str, path: Path) -> str:
    try:
        return str(Path(real).relative_to(path.resolve().parent))
    except ValueError:
        return real


_TF_MESSAGE = re.compile(r" : '(.*)'\s*$", re.S)


def _first_line(exc: BaseException) -> str:
    """The message of an OpenUSD error without its C++ location, on one line."""
    raw = _text(exc)
    found = _TF_MESSAGE.search(raw)
    text = " ".join((found.group(1) if found else raw).split())
    return text[:300]


class _Diagnostics:
    """Collects OpenUSD's error and warning diagnostics while reading (the delegate prints
    them otherwise), so a failure can say why in one line."""

    def __init__(self, tf: Any) -> None:
        self._tf = tf
        self.messages: list[str] = []

    def __enter__(self) -> _Diagnostics:
        try:  # while it lives, USD's warnings are collected instead of printed
            from pxr import UsdUtils

            self._delegate: Any = UsdUtils.CoalescingDiagnosticDelegate()
        except (ImportError, AttributeError):
            self._delegate = None
        mark = getattr(self._tf, "Error", None)
        self._mark = mark.Mark() if mark is not None and hasattr(mark, "Mark") else None
        if self._mark is not None:
            self._mark.SetMark()
        return self

    def __exit__(self, *exc: object) -> None:
        if self._mark is not None:
            for err in self._mark.GetErrors():
                self.messages.append(" ".join(_text(err, "commentary").split()))
            self._mark.Clear()
        self._delegate = None

    def cause(self) -> str:
        if self._mark is not None:
            for err in self._mark.GetErrors():
                self.messages.append(" ".join(_text(err, "commentary").split()))
        return f": {self.messages[0][:300]}" if self.messages else ""


def _text(thing: Any, attribute: str | None = None) -> str:
    """``str`` of an OpenUSD error (or of one of its attributes): its message quotes the
    layer's bytes, which need not be UTF-8 (pxr then raises while converting it)."""
    try:
        return str(getattr(thing, attribute) if attribute else thing)
    except UnicodeError:
        return "(the message quotes bytes that are not UTF-8: the layer is corrupt)"
