"""Read COLLADA like ``trimesh.load`` does through pycollada, without either of them.

What trimesh builds from a ``.dae`` is reproduced array for array:

* the default ``<visual_scene>`` is walked from its ``<node>`` elements; a node's matrix
  is the product of its ``<matrix>``, ``<translate>``, ``<rotate>`` and ``<scale>``
  elements in float32 (pycollada's arithmetic), an instance's transform the float64
  product of its ancestors' matrices, nearly-rigid ones re-orthonormalised by SVD
  (trimesh's ``fix_rigid``); ``<instance_node>`` places a ``<library_nodes>`` node;
* every ``<triangles>``, ``<polylist>`` and ``<polygons>`` of an ``<instance_geometry>``
  is one mesh: corners read through the ``VERTEX`` input (the ``POSITION`` of
  ``<vertices>``) in float32, polygons fanned from their first corner, then vertices
  merged as trimesh's default ``process=True`` does (equal position to 1e-8, and equal
  normal and texture coordinate when the mesh has them);
* pycollada's tolerance is kept: a geometry, node child, transform or material it fails
  to load is left out (a comment inside ``<mesh>``, a broken material reference, an
  index beyond its source...).

``<unit meter>`` is applied by the caller. Anything else that pycollada or trimesh
would treat specially or fail on (zipped files, ``<tristrips>``, ``<lookat>``,
``<instance_controller>``, non-finite coordinates, a malformed effect...) raises
:class:`NeedsTrimesh`. Cameras, lights, animations and controllers carry no triangles
and are not read.
"""

from __future__ import annotations

import numpy as np
from lxml import etree

from urdfinertia.mesh.read.common import NeedsTrimesh, Piece, TooManyFaces, hashable_rows

#: Deepest node nesting (and instance chain) read here; deeper trees go to trimesh.
MAX_DEPTH = 64
_SHADERS = ("phong", "lambert", "blinn", "constant")
_SHADING_KEYS = ("emission", "ambient", "diffuse", "specular", "shininess", "reflective",
                 "reflectivity", "transparent", "transparency", "index_of_refraction")
_COLOR_DEFAULT = (0.0, 0.0, 0.0, 1.0)
_DEFAULTS = {"emission": _COLOR_DEFAULT, "ambient": _COLOR_DEFAULT, "diffuse": _COLOR_DEFAULT,
             "specular": _COLOR_DEFAULT, "shininess": 0.0, "reflective": _COLOR_DEFAULT,
             "reflectivity": 0.0, "transparent": _COLOR_DEFAULT, "transparency": None,
             "index_of_refraction": None}
_XYZ, _ST = 3, 2
#: pycollada's identity for a node without transforms (float32).
_NODE_IDENTITY = np.identity(4, dtype=np.float32)
_NODE_IDENTITY.flags.writeable = False
_EYE = np.eye(4)
_EYE.flags.writeable = False


class _Failed(Exception):
    """pycollada raised one of the errors trimesh tells it to ignore: the item is dropped."""


class _Unsupported(_Failed):
    """pycollada's DaeUnsupportedError (some callers catch it specifically)."""


class _MissingSampler(Exception):
    """pycollada's DaeMissingSampler2D (not one of its ignorable errors)."""

    def __init__(self, sampler_id: str) -> None:
        super().__init__(sampler_id)
        self.sampler_id = sampler_id


class _NoFetch(etree.Resolver):
    """Answers every external-resource request with an empty document."""

    def resolve(self, url, pubid, context):  # noqa: ANN001 - lxml's signature
        return self.resolve_string("", context)


def _parser() -> etree.XMLParser:
    """:func:`xml_safety.safe_parser` with ``huge_tree``: pycollada parses that way, and
    real meshes hold float arrays longer than libxml2's default 10 MB text limit."""
    parser = etree.XMLParser(
        resolve_entities=False, no_network=True, load_dtd=False, dtd_validation=False,
        attribute_defaults=False, huge_tree=True, remove_comments=False, remove_pis=False,
        strip_cdata=False)
    parser.resolvers.add(_NoFetch())
    return parser


def read_dae(data: bytes, max_faces: int) -> list[Piece]:
    """Every triangle-set instance of a COLLADA document, in trimesh's scene order.

    The caller has refused hostile XML (entities, external DTDs) already.

    Raises
    ------
    TooManyFaces
        The instances hold more than ``max_faces`` triangles (counted before any
        instance's arrays are built).
    NeedsTrimesh
        Input this module does not reproduce exactly (see the module docstring).
    """
    try:
        root = etree.fromstring(data, parser=_parser())
    except etree.XMLSyntaxError as exc:
        raise NeedsTrimesh(f"XML: {exc}") from None
    if root.getroottree().docinfo.doctype:
        raise NeedsTrimesh("document type declaration (parsed differently by pycollada)")
    return _Document(root).pieces(max_faces)


# --- sources and primitives --------------------------------------------------------------

class _Source:
    """A ``<source>`` with a ``<float_array>`` (pycollada's FloatSource)."""

    def __init__(self, sid: str | None, data: np.ndarray, components: tuple) -> None:
        self.id = sid
        self.data = data  # (rows, len(components)) float32
        self.components = components


def _check_source(source: _Source, n_components: int, max_index: int) -> None:
    """pycollada's ``checkSource``: enough rows, right number of components."""
    if len(source.data) <= max_index or len(source.components) != n_components:
        raise _Failed("source too short or of the wrong shape")


class _TriangleSet:
    """pycollada's TriangleSet: ``index`` is (n, 3, inputs) int32."""

    def __init__(self, sources: dict, material: str | None, index: np.ndarray) -> None:
        if "VERTEX" not in sources:
            raise _Failed("no VERTEX input")
        self.sources = sources
        self.material = material
        self.index = index
        self.index.shape = (-1, 3, _input_count(sources))
        self._pieces: dict[bool, tuple[np.ndarray, np.ndarray]] = {}
        if len(self.index) == 0:
            return
        for semantic, n_components, first_only in (
                ("VERTEX", _XYZ, True), ("NORMAL", _XYZ, True), ("TEXCOORD", _ST, False),
                ("TEXTANGENT", _XYZ, False), ("TEXBINORMAL", _XYZ, False)):
            for offset, source in sources.get(semantic, [])[:1 if first_only else None]:
                _check_source(source, n_components, np.max(self.index[:, :, offset]))

    @property
    def n_faces(self) -> int:
        return len(self.index)

    def finite(self) -> bool:
        """Whether every corner's position is finite (trimesh drops the other corners)."""
        offset, source = self.sources["VERTEX"][0]
        return bool(np.isfinite(source.data[self.index[:, :, offset]]).all())

    def arrays(self, textured: bool) -> tuple[np.ndarray, np.ndarray]:
        """Vertices and faces of trimesh's mesh for this set, after its vertex merge.

        ``textured``: the instance binds the set's material, so trimesh attaches texture
        coordinates, and vertices with different ones stay apart.
        """
        key = textured and bool(self.sources.get("TEXCOORD"))
        if key not in self._pieces:
            self._pieces[key] = self._build(key)
        return self._pieces[key]

    def _build(self, with_uv: bool) -> tuple[np.ndarray, np.ndarray]:
        """trimesh's mesh (one vertex per corner, ``process=True``) after its vertex merge.

        Corners merge when their positions (times 1e8), normals (times 100) and, with
        ``with_uv``, texture coordinates (times 1e4) round to the same integers; the
        first corner of each group is kept, groups numbered in that order. The rounded
        keys are computed per source row, so corners are compared by group numbers.
        """
        offset, source = self.sources["VERTEX"][0]
        corner = self.index[:, :, offset].reshape(-1)
        positions = np.asarray(source.data, dtype=np.float64)
        finite = np.isfinite(positions).all(axis=1)
        if not finite[corner].all():
            raise NeedsTrimesh("non-finite coordinates (trimesh drops them)")
        key, span = _row_groups(_rounded(np.where(finite[:, None], positions, 0.0), 10 ** 8))
        key = key[corner]
        attributes = []
        if with_uv:
            attributes.append((self.sources["TEXCOORD"][0], 10 ** 4))
        if self.sources.get("NORMAL"):
            attributes.append((self.sources["NORMAL"][0], 10 ** 2))
        for (offset, source), scale in attributes:
            index = self.index[:, :, offset].reshape(-1)
            if index.size and index.min() < -len(source.data):
                raise NeedsTrimesh("index out of range (trimesh fails)")
            groups, count = _row_groups(_rounded(source.data, scale))
            groups = groups[index]
            if span * count >= 2 ** 62:
                _, key = np.unique(key, return_inverse=True)
                span = int(key.max()) + 1
            key = key * count + groups
            span *= count
        if self.sources.get("COLOR"):
            offset, source = self.sources["COLOR"][0]
            index = self.index[:, :, offset]
            if (source.data.shape[1] not in (3, 4) or index.min() < -len(source.data)
                    or index.max() >= len(source.data)):
                raise NeedsTrimesh("vertex colours trimesh may reject")
        _, inverse = np.unique(key, return_inverse=True)
        first = np.full(int(inverse.max()) + 1, len(key), dtype=np.int64)
        np.minimum.at(first, inverse, np.arange(len(key)))
        order = first.argsort()
        faces = order.argsort()[inverse].reshape((-1, 3)).astype(np.int64)
        return positions[corner[first[order]]], faces


def _rounded(values: np.ndarray, scale: int) -> np.ndarray:
    """trimesh's merge key of one attribute: ``round(value * scale)`` as int64."""
    with np.errstate(invalid="ignore"):
        return (np.asarray(values, dtype=np.float64) * scale).round().astype(np.int64)


def _mix(words: np.ndarray) -> np.ndarray:
    """splitmix64's finaliser: a uint64 hash in which every input bit moves every output bit."""
    words = words ^ (words >> np.uint64(30))
    words *= np.uint64(0xBF58476D1CE4E5B9)
    words ^= words >> np.uint64(27)
    words *= np.uint64(0x94D049BB133111EB)
    return words ^ (words >> np.uint64(31))


def _row_groups(rows: np.ndarray) -> tuple[np.ndarray, int]:
    """A group number per row of an int64 (n, k) array, and the number of groups.

    Equal rows get equal numbers: rows are hashed, and the grouping is checked against
    the rows themselves (an exact byte-wise grouping is used after a hash collision).
    """
    if len(rows) == 0:
        return np.zeros(0, dtype=np.int64), 0
    rows = np.ascontiguousarray(rows, dtype=np.int64)
    words = rows.view(np.uint64)
    digest = _mix(words[:, 0])
    for j in range(1, rows.shape[1]):
        digest = _mix(digest ^ words[:, j])
    _, groups = np.unique(digest, return_inverse=True)
    count = int(groups.max()) + 1
    sample = np.empty(count, dtype=np.intp)
    sample[groups] = np.arange(len(rows))  # some row of each group
    if not np.array_equal(rows, rows[sample[groups]]):
        _, groups = np.unique(hashable_rows(rows), return_inverse=True)
        count = int(groups.max()) + 1
    return groups, count


class _Polylist:
    """pycollada's Polylist (and Polygons): fanned into a triangle set when instanced."""

    def __init__(self, sources: dict, material: str | None, index: np.ndarray,
                 vcounts: np.ndarray) -> None:
        if len(sources) == 0 or "VERTEX" not in sources:
            raise _Failed("no VERTEX input")
        self.sources = sources
        self.material = material
        self.index = index
        self.index.shape = (-1, _input_count(sources))
        self.vcounts = vcounts
        self.nvertices = np.sum(self.vcounts) if len(self.index) > 0 else 0
        self.polyends = np.cumsum(self.vcounts)
        self.polyindex = np.dstack((self.polyends - self.vcounts, self.polyends))[0]
        self._triangles: _TriangleSet | None = None
        if len(self.index) == 0:
            return
        for semantic, n_components, first_only in (
                ("VERTEX", _XYZ, True), ("NORMAL", _XYZ, True), ("TEXCOORD", _ST, False)):
            for offset, source in sources.get(semantic, [])[:1 if first_only else None]:
                _check_source(source, n_components, np.max(self.index[:, offset]))

    def triangles(self) -> _TriangleSet:
        """pycollada's ``Polylist.triangleset`` (fan from each polygon's first corner)."""
        if self._triangles is None:
            selector = np.zeros(self.nvertices) == 0
            selector[self.polyindex[:, 1] - 1] = False
            selector[self.polyindex[:, 1] - 2] = False
            selector = np.arange(self.nvertices)[selector]
            first = np.arange(self.nvertices)
            first = first - np.repeat(self.polyends - self.vcounts, self.vcounts)
            first = first[selector]
            if len(self.index) > 0:
                tri = np.dstack((self.index[selector - first], self.index[selector + 1],
                                 self.index[selector + 2]))
                tri = np.swapaxes(tri, 1, 2).flatten()
            else:
                tri = np.array([], dtype=self.index.dtype)
            try:
                self._triangles = _TriangleSet(self.sources, self.material, tri)
            except _Failed:
                raise NeedsTrimesh("polygons that trimesh fails to triangulate") from None
        return self._triangles


def _input_count(sources: dict) -> int:
    """Index values per corner: one more than the largest input offset."""
    return max(max(offset for offset, _ in inputs) for inputs in sources.values()
               if len(inputs) > 0) + 1


# --- the scene graph -------------------------------------------------------------------

class _Geometry:
    def __init__(self, gid: str, primitives: list) -> None:
        self.id = gid
        self.primitives = primitives


class _GeometryInstance:
    def __init__(self, geometry: _Geometry, symbols: set) -> None:
        self.geometry = geometry
        self.symbols = symbols  # material symbols bound by the instance

    def triangle_sets(self) -> list[tuple[_TriangleSet, bool]]:
        """(triangle set, textured) for each primitive trimesh turns into a mesh."""
        out = []
        for primitive in self.geometry.primitives:
            if isinstance(primitive, _Polylist):
                primitive = primitive.triangles()
            elif not isinstance(primitive, _TriangleSet):
                continue  # lines
            if primitive.n_faces == 0:
                continue
            if self.geometry.id == "world":
                raise NeedsTrimesh("geometry named 'world' collides with trimesh's root")
            out.append((primitive, primitive.material in self.symbols))
        return out


class _Node:
    def __init__(self, nid: str | None, matrix: np.ndarray, children: list) -> None:
        self.id = nid
        self.matrix = matrix
        self.children = children


class _Effect:
    """The shading values trimesh's ``_parse_material`` reads from a pycollada Effect."""

    def __init__(self, props: dict) -> None:
        self.props = props


class _Sampler:
    def __init__(self, image_id: str | None) -> None:
        self.image_id = image_id


class _Surface:
    def __init__(self, image_id: str | None) -> None:
        self.image_id = image_id


class _Map:
    """A ``<texture>`` shading value."""


class _Document:
    """One parsed COLLADA document, loaded the way pycollada loads it."""

    def __init__(self, root: etree._Element) -> None:
        self.root = root
        namespace = root.tag.split("}")[0].lstrip("{")
        self.ns = "{" + namespace + "}"
        self.images: set[str | None] = set()
        self.effects: dict[str | None, _Effect] = {}
        self.materials: dict[str | None, _Effect] = {}
        self.geometries: dict[str, _Geometry] = {}
        self.library_nodes: dict[str | None, _Node] = {}
        self._counted: set[_TriangleSet] = set()

    def tag(self, name: str) -> str:
        return self.ns + name

    def _library(self, library: str, item: str) -> list[etree._Element]:
        return [el for lib in self.root.findall(self.tag(library))
                for el in lib.findall(self.tag(item))]

    # --- loading -----------------------------------------------------------------------

    def pieces(self, max_faces: int) -> list[Piece]:
        """Load the libraries and the default scene; the instances in trimesh's order."""
        for el in self._library("library_images", "image"):
            if el.find(self.tag("init_from")) is not None:
                self.images.add(el.get("id"))
        for el in self._library("library_effects", "effect"):
            try:
                self.effects[el.get("id")] = self._effect(el)
            except _Failed:
                pass
        materials = []
        for el in self._library("library_materials", "material"):
            try:
                effect = self._material(el)
            except _Failed:
                continue
            materials.append(effect)
            self.materials[el.get("id")] = effect
        for effect in materials:
            _check_trimesh_material(effect)
        for el in self._library("library_geometries", "geometry"):
            if el.find(self.tag("mesh")) is None:
                continue
            try:
                geometry = self._geometry(el)
            except _Failed:
                continue
            self.geometries[geometry.id] = geometry
        for el in self._library("library_nodes", "node"):
            node = self._node(el, {}, 0)
            self.library_nodes[node.id] = node
        scenes = {}
        for el in self._library("library_visual_scenes", "visual_scene"):
            scenes[el.get("id")] = self._visual_scene(el)
        ref = self.root.find(f"{self.tag('scene')}/{self.tag('instance_visual_scene')}")
        url = None if ref is None else ref.get("url")
        if url is None or not url.startswith("#") or url[1:] not in scenes:
            raise NeedsTrimesh("no default scene (trimesh fails)")
        nodes = scenes[url[1:]]
        memo: dict = {}
        total = sum(self._faces_below(node, memo, 0) for node in nodes)
        if total > max_faces:
            if not all(triangles.finite() for triangles in self._counted):
                raise NeedsTrimesh("trimesh drops non-finite corners before counting")
            raise TooManyFaces(total)
        out: list[Piece] = []
        for node in nodes:
            self._place(node, _EYE, out)
        return out

    def _effect(self, el: etree._Element) -> _Effect:
        """pycollada's ``Effect.load`` as far as trimesh's material reading depends on it."""
        profile = el.find(self.tag("profile_COMMON"))
        if profile is None:
            raise _Failed("no profile_COMMON")
        if profile.find(self.tag("image")) is not None:
            raise NeedsTrimesh("effect-local image")
        scope: dict = {}
        self._effect_params(profile, scope)
        technique = profile.find(self.tag("technique"))
        if technique is None:
            raise NeedsTrimesh("effect without technique (pycollada fails)")
        self._effect_params(technique, scope)
        shader = None
        for name in _SHADERS:
            shader = technique.find(self.tag(name))
            if shader is not None:
                break
        if shader is None:
            raise _Failed("no shader")
        props = {}
        for key in _SHADING_KEYS:
            pnode = shader.find(self.tag(key))
            if pnode is None:
                props[key] = None
                continue
            try:
                props[key] = self._shading_value(pnode, scope)
            except _MissingSampler as exc:
                if exc.sampler_id in self.images:
                    scope[exc.sampler_id + "-surface"] = surface = _Surface(exc.sampler_id)
                    scope[exc.sampler_id] = _Sampler(surface.image_id)
                    try:
                        props[key] = self._shading_value(pnode, scope)
                    except _Unsupported:
                        props[key] = None
            except _Unsupported:
                props[key] = None
        bump = el.find(f".//{self.tag('extra')}//{self.tag('texture')}")
        if bump is not None:
            try:
                self._map(bump, scope)
            except _MissingSampler:
                raise NeedsTrimesh("bump map without sampler (pycollada fails)") from None
        for key, default in _DEFAULTS.items():
            value = props.get(key, default)
            if isinstance(value, tuple) and len(value) < 4:
                value = tuple(value) + (0.0,) * max(3 - len(value), 0)
                value = value + (1.0,) * (4 - len(value))
            props[key] = value
        return _Effect(props)

    def _effect_params(self, parent: etree._Element, scope: dict) -> None:
        """pycollada's ``getEffectParameters``: surfaces, samplers and float params."""
        for param in parent.findall(self.tag("newparam")):
            surface = param.find(self.tag("surface"))
            sampler = param.find(self.tag("sampler2D"))
            if surface is not None:
                if surface.get("type") != "2D":
                    raise _Failed("surface not 2D")
                init = surface.find(self.tag("init_from"))
                if init is None:
                    raise _Failed("surface without image")
                if init.text in scope:
                    raise NeedsTrimesh("surface naming a local parameter")
                if init.text not in self.images:
                    raise _Failed("surface image not found")
                scope[param.get("sid")] = _Surface(init.text)
            elif sampler is not None:
                source = sampler.find(self.tag("source"))
                if source is None:
                    raise _Failed("sampler without source")
                target = scope.get(source.text)
                if not isinstance(target, _Surface):
                    if source.text is None:
                        raise NeedsTrimesh("sampler with an empty source (pycollada fails)")
                    raise _Failed("sampler surface not found")
                scope[param.get("sid")] = _Sampler(target.image_id)
            else:
                value = None
                for kind in ("float", "float2", "float3", "float4"):
                    value = param.find(self.tag(kind))
                    if value is not None:
                        break
                sid = param.get("sid")
                if value is not None and sid and value.text is not None:
                    try:
                        scope[sid] = [float(v) for v in value.text.split()]
                    except ValueError:
                        raise NeedsTrimesh("malformed float parameter") from None

    def _shading_value(self, pnode: etree._Element, scope: dict) -> object:
        """pycollada's ``_loadShadingParam``: the first child decides."""
        children = list(pnode)
        if not children:
            raise _Failed("empty shading parameter")
        child = children[0]
        if child.tag == self.tag("color"):
            if child.text is None:
                raise NeedsTrimesh("empty colour (pycollada fails)")
            try:
                return tuple(float(v) for v in child.text.split())
            except ValueError:
                raise _Failed("malformed colour") from None
        if child.tag == self.tag("float"):
            try:
                return float(child.text)
            except (TypeError, ValueError):
                raise NeedsTrimesh("malformed float (pycollada fails)") from None
        if child.tag == self.tag("texture"):
            return self._map(child, scope)
        if child.tag == self.tag("param"):
            ref = child.get("ref")
            return scope[ref] if ref is not None and ref in scope else None
        raise _Unsupported("unknown shading value")

    def _map(self, el: etree._Element, scope: dict) -> _Map:
        """pycollada's ``Map.load``: the sampler by sid, else by its image's id."""
        sampler_id = el.get("texture")
        sampler = scope.get(sampler_id)
        if sampler is None:
            for candidate in scope.values():
                if isinstance(candidate, _Sampler) and candidate.image_id == sampler_id:
                    sampler = candidate
        if not isinstance(sampler, _Sampler):
            if sampler_id is None:
                raise NeedsTrimesh("texture without sampler (pycollada fails)")
            raise _MissingSampler(sampler_id)
        return _Map()

    def _material(self, el: etree._Element) -> _Effect:
        instance = el.find(self.tag("instance_effect"))
        if instance is None:
            raise _Failed("material without effect")
        url = instance.get("url")
        if url is None:
            raise NeedsTrimesh("effect reference without url (pycollada fails)")
        if not url.startswith("#") or url[1:] not in self.effects:
            raise _Failed("effect not found")
        return self.effects[url[1:]]

    def _geometry(self, el: etree._Element) -> _Geometry:
        """pycollada's ``Geometry.load``."""
        mesh = el.find(self.tag("mesh"))
        sources: dict = {}
        vertices = None
        primitive_nodes = []
        for child in mesh:
            tag = child.tag
            if tag == self.tag("source"):
                source = self._source(child)
                sources[source.id] = source
            elif tag == self.tag("vertices"):
                vertices = child
            elif tag in (self.tag("triangles"), self.tag("polylist"), self.tag("polygons"),
                         self.tag("lines")):
                primitive_nodes.append(child)
            elif tag in (self.tag("tristrips"), self.tag("trifans")):
                raise NeedsTrimesh("triangle strips and fans")
            elif tag != self.tag("extra"):
                raise _Failed("unknown element in <mesh>")  # comments included
        if vertices is not None:
            inputs = {}
            for inp in vertices.iterfind(self.tag("input")):
                semantic, ref = inp.get("semantic"), inp.get("source")
                if not semantic or not ref or not ref.startswith("#"):
                    raise _Failed("bad <vertices> input")
                inputs[semantic] = sources.get(ref[1:])
            vid = vertices.get("id")
            if not vid or len(inputs) == 0 or "POSITION" not in inputs:
                raise _Failed("bad <vertices>")
            sources[vid] = inputs
        primitives = []
        for node in primitive_nodes:
            tag = node.tag
            if tag == self.tag("triangles"):
                primitives.append(self._triangles(node, sources))
            elif tag == self.tag("polylist"):
                primitives.append(self._polylist(node, sources))
            elif tag == self.tag("polygons"):
                primitives.append(self._polygons(node, sources))
            else:
                self._lines(node, sources)
                primitives.append(None)
        return _Geometry(el.get("id") or "", primitives)

    def _source(self, el: etree._Element) -> _Source:
        """pycollada's ``FloatSource.load`` (float32, NaN read as 0)."""
        array = el.find(self.tag("float_array"))
        if array is None:
            if (el.find(self.tag("IDREF_array")) is not None
                    or el.find(self.tag("Name_array")) is not None):
                raise NeedsTrimesh("IDREF or Name source in a mesh")
            raise _Failed("source without array")
        text = array.text
        if text is None or text.isspace():
            data = np.array([], dtype=np.float32)
        else:
            try:
                data = np.fromstring(text, dtype=np.float32, sep=" ")
            except ValueError:
                raise _Failed("malformed float array") from None
            data[np.isnan(data)] = 0
        params = el.findall(f"{self.tag('technique_common')}/{self.tag('accessor')}/"
                            f"{self.tag('param')}")
        if not params:
            raise _Failed("source without accessor")
        components = [param.get("name") for param in params]
        if components == ["U", "V"]:
            components = ["S", "T"]
        if components == ["S", "T", "P"]:
            components = ["S", "T"]
            if data.size % 3:
                raise NeedsTrimesh("STP source of the wrong size (pycollada fails)")
            data = np.delete(data.reshape((-1, 3)), -1, 1).reshape(-1)
        if data.size % len(components) != 0:
            raise _Failed("source size not a multiple of its components")
        return _Source(el.get("id"), data.reshape((-1, len(components))), tuple(components))

    def _inputs(self, el: etree._Element, scope: dict) -> dict:
        """pycollada's ``Primitive._getInputs``: semantic -> [(offset, source)]."""
        raw = []
        for inp in el.findall(self.tag("input")):
            offset = inp.get("offset")
            if offset is None or inp.get("source") is None:
                raise NeedsTrimesh("input without offset or source (pycollada fails)")
            try:
                offset = int(offset)
            except ValueError:
                raise _Failed("malformed offset") from None
            raw.append((offset, inp.get("semantic"), inp.get("source")))
        inputs: dict = {}
        for offset, semantic, ref in raw:
            target = scope.get(ref[1:])
            if semantic == "VERTEX" and isinstance(target, dict):
                for inner, source in target.items():
                    if not isinstance(source, _Source):
                        raise NeedsTrimesh("<vertices> input naming no source")
                    name = "VERTEX" if inner == "POSITION" else inner
                    inputs.setdefault(name, []).append((offset, source))
            elif not isinstance(target, dict):
                if len(ref) < 2 or ref[0] != "#" or ref[1:] not in scope:
                    raise _Failed("input source not found")
                inputs.setdefault(semantic, []).append((offset, scope[ref[1:]]))
        return inputs

    @staticmethod
    def _index(text: str | None) -> np.ndarray:
        """A ``<p>`` or ``<vcount>`` as int32 (pycollada's parse)."""
        if text is None or text.isspace():
            return np.array([], dtype=np.int32)
        try:
            return np.fromstring(text, dtype=np.int32, sep=" ")
        except ValueError:
            raise _Failed("malformed index") from None

    def _triangles(self, el: etree._Element, scope: dict) -> _TriangleSet:
        ps = el.findall(self.tag("p"))
        if not ps:
            raise _Failed("triangles without <p>")
        inputs = self._inputs(el, scope)
        if not inputs:
            raise NeedsTrimesh("triangles without inputs (pycollada fails)")
        index = self._index(ps[0].text)
        return _guarded(_TriangleSet, inputs, el.get("material"), index)

    def _polylist(self, el: etree._Element, scope: dict) -> _Polylist:
        p, vcount = el.find(self.tag("p")), el.find(self.tag("vcount"))
        if p is None or vcount is None:
            raise _Failed("polylist without <p> or <vcount>")
        vcounts = self._index(vcount.text)
        inputs = self._inputs(el, scope)
        index = self._index(p.text)
        return _guarded(_Polylist, inputs, el.get("material"), index, vcounts)

    def _polygons(self, el: etree._Element, scope: dict) -> _Polylist:
        polygons = []
        for p in el.findall(self.tag("p")):
            if p.text is None or (p.text and p.text.isspace()):
                raise NeedsTrimesh("empty polygon (pycollada misreads it)")
            try:
                polygons.append(np.fromstring(p.text, dtype=np.int32, sep=" "))
            except ValueError:
                raise _Failed("malformed polygon") from None
        inputs = self._inputs(el, scope)
        if not inputs:
            raise NeedsTrimesh("polygons without inputs (pycollada fails)")
        per_corner = _input_count(inputs)
        vcounts = np.zeros(len(polygons), dtype=np.int32)
        for i, polygon in enumerate(polygons):
            vcounts[i] = len(polygon) / per_corner
        index = np.concatenate(polygons) if polygons else np.array([], dtype=np.int32)
        return _guarded(_Polylist, inputs, el.get("material"), index, vcounts)

    def _lines(self, el: etree._Element, scope: dict) -> None:
        """Load ``<lines>`` only to fail where pycollada fails (they hold no triangles)."""
        p = el.find(self.tag("p"))
        if p is None:
            raise _Failed("lines without <p>")
        inputs = self._inputs(el, scope)
        index = self._index(p.text)
        if not inputs.get("VERTEX"):
            raise _Failed("lines without VERTEX")
        try:
            index.shape = (-1, 2, _input_count(inputs))
        except ValueError:
            raise NeedsTrimesh("lines index of the wrong size (pycollada fails)") from None
        if len(index) == 0:
            return
        for semantic, n_components, first_only in (
                ("VERTEX", _XYZ, True), ("NORMAL", _XYZ, True), ("TEXCOORD", _ST, False)):
            for offset, source in inputs.get(semantic, [])[:1 if first_only else None]:
                _check_source(source, n_components, np.max(index[:, :, offset]))

    # --- nodes -------------------------------------------------------------------------

    def _visual_scene(self, el: etree._Element) -> list[_Node]:
        """pycollada's ``Scene.load``: its top-level ``<node>`` elements."""
        nodes: list[_Node] = []
        scope: dict = {}
        for child in el.findall(self.tag("node")):
            node = self._node(child, scope, 0)
            nodes.append(node)
            if node.id and node.id not in scope:
                scope[node.id] = node
        return nodes

    def _node(self, el: etree._Element, scope: dict, depth: int) -> _Node:
        """pycollada's ``Node.load``: children and transforms it fails on are dropped."""
        if depth > MAX_DEPTH:
            raise NeedsTrimesh("nodes nested too deeply")
        children: list = []
        transforms: list[np.ndarray] = []
        for child in el:
            tag = child.tag
            if tag == self.tag("node"):
                children.append(self._node(child, scope, depth + 1))
            elif tag in (self.tag("translate"), self.tag("rotate"), self.tag("scale"),
                         self.tag("matrix")):
                matrix = self._transform(child)
                if matrix is not None:
                    transforms.append(matrix)
            elif tag == self.tag("instance_geometry"):
                try:
                    children.append(self._geometry_instance(child))
                except _Failed:
                    pass
            elif tag == self.tag("instance_node"):
                url = child.get("url")
                if url is None:
                    raise NeedsTrimesh("instance_node without url (pycollada fails)")
                if not url.startswith("#"):
                    continue
                target = scope.get(url[1:]) or self.library_nodes.get(url[1:])
                if target is None:
                    raise NeedsTrimesh("instance_node before its node (pycollada retries)")
                children.append(target)
            elif tag in (self.tag("instance_camera"), self.tag("instance_light")):
                if child.get("url") is None:
                    raise NeedsTrimesh("instance without url (pycollada fails)")
            elif tag in (self.tag("instance_controller"), self.tag("lookat")):
                raise NeedsTrimesh(f"<{tag.rsplit('}', 1)[-1]}>")
        if not transforms:
            matrix = _NODE_IDENTITY
        elif len(transforms) == 1:
            matrix = transforms[0].copy()
        else:
            matrix = np.identity(4, dtype=np.float32)
            for transform in transforms:
                matrix = np.dot(matrix, transform)
        return _Node(el.get("id"), matrix, children)

    def _transform(self, el: etree._Element) -> np.ndarray | None:
        """A transform element's float32 matrix, or None where pycollada drops it."""
        if el.text is None:
            raise NeedsTrimesh("empty transform (pycollada fails)")
        if el.text.isspace():
            return None
        try:
            floats = np.fromstring(el.text, dtype=np.float32, sep=" ")
        except ValueError:
            return None
        tag = el.tag
        if tag == self.tag("matrix"):
            if len(floats) != 16:
                return None
            floats.shape = (4, 4)
            return floats
        if tag == self.tag("rotate"):
            if len(floats) != 4:
                return None
            x, y, z, angle = floats
            return _rotation(x, y, z, angle * np.pi / 180.0)
        if len(floats) != 3:
            return None
        matrix = np.identity(4, dtype=np.float32)
        if tag == self.tag("translate"):
            matrix[:3, 3] = [floats[0], floats[1], floats[2]]
        else:
            matrix[0, 0], matrix[1, 1], matrix[2, 2] = floats[0], floats[1], floats[2]
        return matrix

    def _geometry_instance(self, el: etree._Element) -> _GeometryInstance:
        """pycollada's ``GeometryNode.load`` with its material bindings."""
        url = el.get("url")
        if url is None:
            raise NeedsTrimesh("instance_geometry without url (pycollada fails)")
        if not url.startswith("#") or url[1:] not in self.geometries:
            raise _Failed("geometry not found")
        symbols = set()
        path = (f"{self.tag('bind_material')}/{self.tag('technique_common')}/"
                f"{self.tag('instance_material')}")
        for binding in el.findall(path):
            target = binding.get("target")
            if target is None:
                raise NeedsTrimesh("instance_material without target (pycollada fails)")
            if not target.startswith("#") or target[1:] not in self.materials:
                raise _Failed("material not found")
            symbols.add(binding.get("symbol"))
        return _GeometryInstance(self.geometries[url[1:]], symbols)

    # --- instances ---------------------------------------------------------------------

    def _faces_below(self, node: object, memo: dict, depth: int) -> int:
        """Triangles trimesh creates under ``node`` (shared subtrees counted once each)."""
        if depth > MAX_DEPTH:
            raise NeedsTrimesh("instances nested too deeply")
        key = id(node)
        if key not in memo:
            if isinstance(node, _GeometryInstance):
                sets = [triangles for triangles, _ in node.triangle_sets()]
                self._counted.update(sets)
                memo[key] = sum(triangles.n_faces for triangles in sets)
            elif isinstance(node, _Node):
                memo[key] = sum(self._faces_below(c, memo, depth + 1) for c in node.children)
            else:
                memo[key] = 0
        return memo[key]

    def _place(self, node: object, parent: np.ndarray, out: list[Piece]) -> None:
        """trimesh's ``_parse_node``: one piece per triangle set of every instance."""
        if isinstance(node, _GeometryInstance):
            transform = _fix_rigid(np.array(parent, dtype=np.float64))
            for triangles, textured in node.triangle_sets():
                vertices, faces = triangles.arrays(textured)
                out.append(Piece(vertices, faces, transform))
        elif isinstance(node, _Node):
            for child in node.children:
                self._place(child, np.dot(parent, node.matrix), out)


def _guarded(kind: type, *args: object) -> object:
    """Build a primitive; a wrongly sized index makes pycollada fail outright."""
    try:
        return kind(*args)
    except ValueError:
        raise NeedsTrimesh("index of the wrong size (pycollada fails)") from None


def _rotation(x: np.float32, y: np.float32, z: np.float32, angle: np.float32) -> np.ndarray:
    """pycollada's ``makeRotationMatrix`` (float32 throughout)."""
    c = np.cos(angle)
    s = np.sin(angle)
    t = (1 - c)
    return np.array([[t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0],
                     [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0],
                     [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0],
                     [0, 0, 0, 1]],
                    dtype=np.float32)


def _fix_rigid(matrix: np.ndarray, max_deviance: float = 1e-5) -> np.ndarray:
    """trimesh's ``fix_rigid``: a rotation off by less than ``max_deviance`` is re-fitted."""
    check = np.abs(np.dot(matrix[:3, :3], matrix[:3, :3].T) - _EYE[:3, :3]).max()
    if check > 1e-13 and check < max_deviance:
        u, _, v = np.linalg.svd(matrix[:3, :3])
        repaired = np.eye(4)
        repaired[:3, :3] = np.dot(u, v)
        repaired[:3, 3] = matrix[:3, 3]
        if not np.allclose(repaired, matrix, atol=max_deviance):
            raise NeedsTrimesh("transform trimesh cannot repair")
        return repaired
    return matrix


def _check_trimesh_material(effect: _Effect) -> None:
    """Raise where trimesh's ``_parse_material`` fails on this effect's values."""
    props = effect.props
    diffuse = props["diffuse"]
    if not (diffuse is None or isinstance(diffuse, _Map)
            or (isinstance(diffuse, tuple) and len(diffuse) == 4)):
        raise NeedsTrimesh("diffuse value trimesh may reject")
    emission = props["emission"]
    if not (emission is None or isinstance(emission, _Map)):
        if not isinstance(emission, tuple):
            raise NeedsTrimesh("emission value trimesh may reject")
        if np.array(emission[:3], dtype=np.float64).min() < -1e-5:
            raise NeedsTrimesh("negative emission (trimesh fails)")
    shininess = props["shininess"]
    if isinstance(shininess, float) and shininess == -2.0:
        raise NeedsTrimesh("shininess -2 (trimesh divides by zero)")
    transparent = props["transparent"]
    if not (transparent is None or isinstance(transparent, _Map)
            or isinstance(transparent, tuple)):
        raise NeedsTrimesh("transparent value trimesh may reject")
