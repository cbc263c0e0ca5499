"""COLLADA triangles as `trimesh.exchange.dae.load_collada` finds them, at less cost.

pycollada parses every `<source>` of every geometry (normals, texture coordinates,
colours) with `numpy.fromstring`, which is most of the time of reading a COLLADA file,
although the mesh needs only the positions and the `<p>` indices. Here pycollada still
loads the document (the same lxml parse, asset, effects, materials, nodes and scenes, so
node transforms, instance and material binding rules are its own), but the geometry
library is read by `_mesh_primitives`: positions and indices with the same
`numpy.fromstring` calls (float32, NaN as 0, int32), and of the other sources only
what pycollada checks (value counts, component names, index ranges), counted without
parsing the numbers. The scene is then walked as trimesh walks it (the same
`numpy.dot` of float64 parent and float32 node matrices).

Whatever this reader does not reproduce exactly raises `NeedsPycollada`: a
geometry pycollada would leave out for an error, `<polygons>`, `<tristrips>`,
`<trifans>`, controllers, numbers other than plain decimals, a polygon of fewer than
three corners, ... The caller then reads the file with trimesh's loader. `<lines>` hold
no triangles; they are only checked as pycollada checks them.
"""

from __future__ import annotations

import io
import warnings
from typing import Any

import numpy as np

from urdfinertia.mesh.read.common import Piece


class NeedsPycollada(Exception):
    """The document holds something only pycollada's own geometry loader reproduces."""


_NUMBER_BYTES = b"0123456789+-.eE \t\n\r\v\f"
"""Bytes a float array may hold for its numbers to be counted without parsing them."""
_NUMBER_OR_SPACE = b"0123456789+-.eE "
_SPACES = bytes.maketrans(b"\t\n\r\v\f", b"     ")
"""White space (numpy's separator " " matches any run of it) as a plain space."""



def read_collada(data: bytes) -> list[Piece]:
    """Every triangle-set instance of a COLLADA document, in its world frame.

    Raises
    ------
    NeedsPycollada
        The document uses something this reader does not reproduce exactly.
    """
    doc = _Document(io.BytesIO(data), ignore=_ignores())
    try:
        return _scene_pieces(doc)
    finally:
        _release(doc)


def _release(doc: Any) -> None:
    """Drop what the document holds, so that its lxml tree and objects are freed now.

    pycollada's document and its parts refer to each other (a bound method, the scene's
    and materials' back references): left alone, the whole parsed file waits for the
    cyclic garbage collector, on top of the arrays the repair then builds. The pieces
    returned hold arrays of their own, not pycollada's.
    """
    doc.__dict__.clear()


def _scene_pieces(doc: Any) -> list[Piece]:
    """The triangle-set instances of `doc`'s default scene, as trimesh walks it."""
    import collada
    from trimesh.exchange.dae import _parse_material

    # what load_collada does with materials (its only use of them that may fail)
    material_map = {m.id: _parse_material(m.effect, None) for m in doc.materials}
    unit = doc.assetInfo.unitmeter
    # load_collada only names the unit (the caller applies it), but this test may fail
    bool(unit is None or np.isclose(unit, 1.0))
    if doc.scene is None:
        raise NeedsPycollada("no default scene")  # load_collada fails on it
    eye = np.eye(4)
    pieces: list[Piece] = []
    stack: list[tuple[Any, np.ndarray]] = [(node, eye) for node in reversed(doc.scene.nodes)]
    while stack:
        node, parent = stack.pop()
        if isinstance(node, collada.scene.GeometryNode):
            for material in node.materials:
                if material.target.id not in material_map:
                    _parse_material(material.target, None)
            for primitive in node.geometry.primitives:
                if not isinstance(primitive, _Triangles):  # a pycollada without our hook
                    raise NeedsPycollada("geometry not read by this module")
                pieces.append(Piece(primitive.vertices, primitive.faces, parent))
        elif isinstance(node, collada.scene.Node) and node.children is not None:
            children = []
            for child in node.children:
                children.append((child, np.dot(parent, node.matrix)))
            stack.extend(reversed(children))
    return pieces


def _ignores() -> list[type]:
    """The pycollada errors `load_collada` ignores (a part that fails is left out)."""
    import collada

    common = collada.common
    return [common.DaeError, common.DaeIncompleteError, common.DaeMalformedError,
            common.DaeBrokenRefError, common.DaeUnsupportedError]


def _document_class() -> type:
    import collada

    class Document(collada.Collada):
        """pycollada's document with this module's geometry library."""

        def _loadGeometry(self) -> None:  # noqa: N802 - pycollada's name
            tag = self.tag
            controllers = self.xmlnode.find(tag("library_controllers"))
            if controllers is not None and len(controllers):
                raise NeedsPycollada("controllers")
            for library in self.xmlnode.findall(tag("library_geometries")):
                for node in library.findall(tag("geometry")):
                    mesh = node.find(tag("mesh"))
                    if mesh is None:
                        continue
                    self.geometries.append(
                        _Geometry(node.get("id") or "", _mesh_primitives(mesh, tag)))

    return Document


_DOCUMENT: type | None = None


def _Document(stream: io.BytesIO, ignore: list[type]) -> Any:  # noqa: N802 - a class
    global _DOCUMENT
    if _DOCUMENT is None:
        _DOCUMENT = _document_class()
    return _DOCUMENT(stream, ignore=ignore)


class _Geometry:
    """What the scene needs of a pycollada Geometry: its id and triangle sets."""

    def __init__(self, id: str, primitives: list[_Triangles]) -> None:
        self.id = id
        self.primitives = primitives


class _Triangles:
    """One triangle set as trimesh keeps it: an unwelded soup, three corners a face."""

    def __init__(self, vertices: np.ndarray) -> None:
        self.vertices = vertices
        self.faces = np.arange(len(vertices), dtype=np.int64).reshape(-1, 3)


class _Source:
    """A `<source>`: its components and number of values, its numbers on demand."""

    def __init__(self, node: Any, tag: Any) -> None:
        array = node.find(tag("float_array"))
        if array is None:
            raise NeedsPycollada("a source without float_array")
        self._array = array  # its text is read when needed (a str the size of the array)
        params = node.findall(f"{tag('technique_common')}/{tag('accessor')}/{tag('param')}")
        if not params:
            raise NeedsPycollada("a source without accessor")
        components = tuple(p.get("name") for p in params)
        self.values = _count_numbers(array.text)
        if components == ("U", "V"):
            components = ("S", "T")
        if components == ("S", "T", "P"):
            if self.values % 3:
                raise NeedsPycollada("texture coordinates not in threes")
            self.values = self.values // 3 * 2
            components = ("S", "T")
            self._stp = True
        else:
            self._stp = False
        if self.values % len(components):
            raise NeedsPycollada("source values not a multiple of its components")
        self.components = components
        self.rows = self.values // len(components)
        self._data: np.ndarray | None = None

    def positions(self) -> np.ndarray:
        """(n, 3) float32: pycollada's `FloatSource.data` of a position source."""
        if self._data is None:
            if self._stp or not _fits(self.components, 3, ("X", "Y", "Z")):
                raise NeedsPycollada("positions without three components")
            text = self._array.text
            if text is None or text.isspace():
                data = np.array([], dtype=np.float32)
            else:
                data = _fromstring(text, np.float32)
                data[np.isnan(data)] = 0
            if len(data) != self.values:
                raise NeedsPycollada("numbers pycollada would count otherwise")
            self._data = data.reshape(-1, 3)
        return self._data


def _fits(components: tuple, count: int, names: tuple) -> bool:
    """pycollada's `checkSource` on components: renamed when the count matches."""
    return len(components) == count or components == names


def _count_numbers(text: str | None) -> int:
    """How many numbers `numpy.fromstring(text, sep=" ")` finds, without parsing them.

    Only text of digits, signs, points, exponent letters and white space is counted
    (anything else, such as `nan`, commas or non-ASCII, raises `NeedsPycollada`):
    the numbers are the runs between white space, counted with bytes methods.
    """
    if not text or text.isspace():
        return 0
    try:
        raw = text.encode("ascii")
    except UnicodeEncodeError:
        raise NeedsPycollada("non-ASCII numbers") from None
    if not raw.translate(None, _NUMBER_OR_SPACE) and b"  " not in raw:
        # the common layout: numbers between single spaces
        return raw.count(b" ") + 1 - raw.startswith(b" ") - raw.endswith(b" ")
    if raw.translate(None, _NUMBER_BYTES):
        raise NeedsPycollada("a float array with other characters")
    spaced = raw.translate(_SPACES).strip(b" ")
    if b"  " in spaced:  # runs of white space: count run starts instead
        words = np.frombuffer(spaced, dtype=np.uint8) != ord(" ")
        return 1 + int(np.count_nonzero(words[1:] & ~words[:-1]))
    return spaced.count(b" ") + 1


def _fromstring(text: str, dtype: type) -> np.ndarray:
    """pycollada's `numpy.fromstring(text, dtype, sep=" ")`; text it would read only in
    part (numpy warns and stops) raises `NeedsPycollada`."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        try:
            return np.fromstring(text, dtype=dtype, sep=" ")
        except (ValueError, DeprecationWarning):
            raise NeedsPycollada("malformed numbers") from None


def _indices(node: Any) -> np.ndarray:
    if node is None or node.text is None or node.text.isspace():
        return np.array([], dtype=np.int32)
    return _fromstring(node.text, np.int32)


def _mesh_primitives(mesh: Any, tag: Any) -> list[_Triangles]:
    """The triangle sets of a `<mesh>`, as pycollada's `Geometry.load` reads them."""
    sources: dict[str | None, _Source] = {}
    vertices = None
    primitives = []
    for node in mesh:
        kind = node.tag
        if kind == tag("source"):
            sources[node.get("id")] = _Source(node, tag)
        elif kind == tag("vertices"):
            if vertices is not None:
                raise NeedsPycollada("several <vertices>")
            vertices = node
        elif kind in (tag("triangles"), tag("polylist"), tag("lines")):
            primitives.append(node)
        elif kind != tag("extra"):
            raise NeedsPycollada(f"mesh element {kind}")
    scope: dict[str | None, Any] = dict(sources)
    if vertices is not None:
        inputs: dict[str, _Source] = {}
        for node in vertices.iterfind(tag("input")):
            semantic, source = node.get("semantic"), node.get("source")
            if not semantic or not source or not source.startswith("#"):
                raise NeedsPycollada("bad <vertices> input")
            if source[1:] not in sources:
                raise NeedsPycollada("a <vertices> input of a missing source")
            inputs[semantic] = sources[source[1:]]
        vertices_id = vertices.get("id")
        if not vertices_id or "POSITION" not in inputs or vertices_id in sources:
            raise NeedsPycollada("bad <vertices>")
        scope[vertices_id] = inputs
    found = []
    for node in primitives:
        if node.tag == tag("lines"):
            _lines(node, scope, tag)
        else:
            found.append(_triangles(node, scope, tag))
    return found


def _inputs(node: Any, scope: dict, tag: Any) -> list[tuple[int, str, _Source]]:
    """(offset, semantic, source) of a primitive's inputs, as pycollada expands them."""
    found = []
    for element in node.findall(tag("input")):
        try:
            offset = int(element.get("offset"))
        except (TypeError, ValueError):
            raise NeedsPycollada("bad input offset") from None
        semantic, source = element.get("semantic"), element.get("source")
        if offset < 0 or not isinstance(source, str) or len(source) < 2 or source[0] != "#":
            raise NeedsPycollada("bad input")
        target = scope.get(source[1:])
        if isinstance(target, dict):
            if semantic != "VERTEX":
                raise NeedsPycollada("a <vertices> input that is not VERTEX")
            for name, expanded in target.items():
                found.append((offset, "VERTEX" if name == "POSITION" else name, expanded))
        elif target is None:
            raise NeedsPycollada("an input of a missing source")
        else:
            found.append((offset, semantic, target))
    return found


def _triangles(node: Any, scope: dict, tag: Any) -> _Triangles:
    """A `<triangles>` or `<polylist>` as trimesh's vertices of its TriangleSet."""
    inputs, width, p = _primitive(node, scope, tag)
    index = _indices(p)
    if node.tag == tag("polylist"):
        index = _fan(index, _indices(node.find(tag("vcount"))), width)
    if index.size % (3 * width):
        raise NeedsPycollada("indices not in whole triangles")
    index = index.reshape(-1, 3, width)
    if len(index) == 0:
        return _Triangles(np.zeros((0, 3)))
    offset, positions = _checked(index, inputs, _TRIANGLE_CHECKS)
    corners = positions.positions()[index[:, :, offset]]
    return _Triangles(np.asarray(corners.reshape(-1, 3), dtype=np.float64))


def _lines(node: Any, scope: dict, tag: Any) -> None:
    """The checks of pycollada's LineSet (a failure leaves the whole geometry out)."""
    inputs, width, p = _primitive(node, scope, tag)
    index = _indices(p)
    if index.size % (2 * width):
        raise NeedsPycollada("indices not in whole lines")
    index = index.reshape(-1, 2, width)
    if len(index):
        _checked(index, inputs, _LINE_CHECKS)


def _primitive(node: Any, scope: dict, tag: Any) -> tuple[list, int, Any]:
    """A primitive's inputs, index width (largest offset + 1) and first `<p>`."""
    inputs = _inputs(node, scope, tag)
    if not any(semantic == "VERTEX" for _, semantic, _ in inputs):
        raise NeedsPycollada("a primitive without VERTEX input")
    p = node.find(tag("p"))
    if p is None:
        raise NeedsPycollada("a primitive without <p>")
    return inputs, max(offset for offset, _, _ in inputs) + 1, p


_TRIANGLE_CHECKS = (("VERTEX", 3, False), ("NORMAL", 3, False), ("COLOR", 0, False),
                    ("TEXCOORD", 2, True), ("TEXTANGENT", 3, True),
                    ("TEXBINORMAL", 3, True))
"""(semantic, components (0: any), every input or the first only) that pycollada's TriangleSet
checks or trimesh gathers, and those its LineSet checks.
"""
_LINE_CHECKS = (("VERTEX", 3, False), ("NORMAL", 3, False), ("TEXCOORD", 2, True))


def _checked(index: np.ndarray, inputs: list, checks: tuple) -> tuple[int, _Source]:
    """The (offset, source) of the positions, after checking `index` (k, corners, width)
    against every checked input's source."""
    if index.min() < 0:
        raise NeedsPycollada("negative indices")
    for semantic, components, every in checks:
        chosen = [(o, s) for o, name, s in inputs if name == semantic]
        for offset, source in chosen if every else chosen[:1]:
            _check(index, offset, source, components)
    return next((o, s) for o, name, s in inputs if name == "VERTEX")


def _check(index: np.ndarray, offset: int, source: _Source, components: int) -> None:
    """pycollada's `checkSource` (and trimesh's gathers): indices within the source, and
    its component count (0: any)."""
    if int(index[..., offset].max()) >= source.rows:
        raise NeedsPycollada("indices beyond their source")
    names = ("X", "Y", "Z") if components == 3 else ("S", "T")
    if components and not _fits(source.components, components, names):
        raise NeedsPycollada("a source with other components")


def _fan(index: np.ndarray, counts: np.ndarray, width: int) -> np.ndarray:
    """pycollada's `Polylist.triangleset()` index: each polygon as a fan about its first
    corner, for polygons of three corners or more that use every index row."""
    if index.size % width:
        raise NeedsPycollada("polylist indices not in whole corners")
    rows = index.reshape(-1, width)
    if len(rows) == 0:
        return index[:0]
    if len(counts) == 0 or counts.min() < 3 or int(counts.sum(dtype=np.int64)) != len(rows):
        raise NeedsPycollada("polygons of fewer than three corners or unused corners")
    ends = np.cumsum(counts, dtype=np.int64)
    starts = ends - counts
    keep = np.ones(len(rows), dtype=bool)
    keep[ends - 1] = False
    keep[ends - 2] = False
    corner = np.flatnonzero(keep)
    first = np.repeat(starts, counts)[corner]
    return np.stack([rows[first], rows[corner + 1], rows[corner + 2]], axis=1).reshape(-1)
