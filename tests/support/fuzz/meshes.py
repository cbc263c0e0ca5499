"""Mutators of mesh files: STL (binary and ASCII), OBJ, COLLADA, PLY and GLB.

Two kinds: geometric mutations change the triangles (a NaN coordinate, huge or tiny
coordinates, a triangle soup, degenerate faces, holes, flipped faces, random triangles)
and write them back in the seed's format; byte and text mutations change the file itself
(truncation, flipped bytes, a wrong face count, ``<unit meter="0">``, an index past the
last vertex, a node scale of zero). Every mutator is ``(data, fmt, rng) -> (kind, bytes)``
and deterministic given ``rng``.
"""

from __future__ import annotations

import io
import json
import random
import re
import struct

import numpy as np

from support.fuzz.mutate import BAD_NUMBERS

_NUMBER = re.compile(rb"(?<![\w.])-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")


# --- reading and writing triangles ---------------------------------------------------

def triangles(data: bytes, fmt: str) -> tuple[np.ndarray, np.ndarray]:
    """The seed's vertices and faces (trimesh, no processing)."""
    import trimesh

    file_type = {"stl-ascii": "stl"}.get(fmt, fmt)
    mesh = trimesh.load(io.BytesIO(data), file_type=file_type, force="mesh", process=False)
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)


def encode(vertices: np.ndarray, faces: np.ndarray, fmt: str) -> bytes:
    """Triangles written in ``fmt``, keeping every value as given (NaN included)."""
    tri = vertices[faces]
    if fmt == "stl":
        out = bytearray(b"fuzz".ljust(80, b" ") + struct.pack("<I", len(tri)))
        records = np.zeros(len(tri), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)),
                                            ("a", "<u2")])
        with np.errstate(all="ignore"):
            records["v"] = tri
        return bytes(out) + records.tobytes()
    if fmt == "stl-ascii":
        lines = ["solid fuzz"]
        for t in tri:
            lines += ["facet normal 0 0 0", " outer loop"]
            lines += [f"  vertex {x!r} {y!r} {z!r}" for x, y, z in t.tolist()]
            lines += [" endloop", "endfacet"]
        return ("\n".join(lines + ["endsolid fuzz", ""])).encode()
    if fmt == "obj":
        lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
        return ("\n".join(lines) + "\n").encode()
    if fmt == "ply":
        head = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\n"
                "property float x\nproperty float y\nproperty float z\n"
                f"element face {len(faces)}\nproperty list uchar int vertex_indices\n"
                "end_header\n").encode()
        v = vertices.astype("<f4").tobytes()
        f = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
        f["n"] = 3
        f["i"] = faces
        return head + v + f.tobytes()
    if fmt == "glb":
        return _glb(vertices, faces)
    if fmt == "dae":
        return _dae(vertices, faces)
    raise ValueError(fmt)


def _glb(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """A minimal GLB: one mesh, float32 positions, uint32 indices."""
    pos = vertices.astype("<f4").tobytes()
    idx = faces.astype("<u4").tobytes()
    finite = vertices[np.isfinite(vertices).all(axis=1)] if len(vertices) else vertices
    lo = finite.min(axis=0).tolist() if len(finite) else [0, 0, 0]
    hi = finite.max(axis=0).tolist() if len(finite) else [0, 0, 0]
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(pos) + len(idx)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(vertices), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": faces.size, "type": "SCALAR"}],
    }
    return pack_glb(doc, pos + idx)


def pack_glb(doc: dict, binary: bytes) -> bytes:
    text = json.dumps(doc, allow_nan=True).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    body = (struct.pack("<I4s", len(text), b"JSON") + text
            + struct.pack("<I4s", len(binary), b"BIN\0") + binary)
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def unpack_glb(data: bytes) -> tuple[dict, bytes] | None:
    try:
        (n,) = struct.unpack_from("<I", data, 12)
        doc = json.loads(data[20: 20 + n])
        (m,) = struct.unpack_from("<I", data, 20 + n)
        return doc, data[28 + n: 28 + n + m]
    except (struct.error, ValueError):
        return None


def _dae(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    pos = " ".join(repr(x) for x in vertices.reshape(-1).tolist())
    idx = " ".join(str(i) for i in faces.reshape(-1).tolist())
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="{vertices.size}">{pos}</float_array>
      <technique_common><accessor source="#pa" count="{len(vertices)}" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="{len(faces)}"><input semantic="VERTEX" source="#v" offset="0"/>
      <p>{idx}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n">
    <instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
""".encode()


# --- geometric mutations -------------------------------------------------------------

def _geometric(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    vertices, faces = triangles(data, fmt)
    gen = np.random.default_rng(rng.randrange(1 << 32))
    kind = rng.choice(("nan", "nan", "huge", "tiny", "far-vertex", "soup", "random-soup",
                       "degenerate", "duplicate", "flip-some", "holes", "flat", "mirror"))
    v, f = vertices.copy(), faces.copy()
    size = float(np.ptp(v, axis=0).max()) if len(v) else 1.0
    if kind == "nan":
        for _ in range(rng.choice((1, 1, 3))):
            v[gen.integers(len(v)), gen.integers(3)] = rng.choice((np.nan, np.inf, -np.inf))
    elif kind == "huge":
        v *= rng.choice((1e4, 1e8, 1e10, 1e20))
    elif kind == "tiny":
        v *= rng.choice((1e-6, 1e-9, 1e-20, 1e-40))
    elif kind == "far-vertex":
        v[gen.integers(len(v))] += rng.choice((1e3, 1e6, 1e9 + 1)) * size
    elif kind == "soup":  # private vertices per face, jittered, shuffled
        f = f[gen.permutation(len(f))]
        v = v[f].reshape(-1, 3) + gen.normal(scale=rng.choice((0, 1e-9, 1e-5)) * size,
                                            size=(3 * len(f), 3))
        f = np.arange(len(v)).reshape(-1, 3)
    elif kind == "random-soup":  # triangles with random corners in the bounding box
        n = rng.choice((50, 500, 3000, 12000))
        lo, hi = v.min(axis=0), v.max(axis=0)
        v = lo + gen.random((3 * n, 3)) * (hi - lo)
        f = np.arange(3 * n).reshape(-1, 3)
    elif kind == "degenerate":
        pick = gen.random(len(f)) < rng.choice((0.1, 0.5, 1.0))
        f[pick, 2] = f[pick, rng.choice((0, 1))]
    elif kind == "duplicate":
        f = np.concatenate([f] * rng.choice((2, 3)))
    elif kind == "flip-some":
        pick = gen.random(len(f)) < rng.choice((0.1, 0.5, 1.0))
        f[pick] = f[pick][:, ::-1]
    elif kind == "holes":
        f = f[gen.random(len(f)) > rng.choice((0.05, 0.3, 0.9))]
    elif kind == "flat":
        v[:, gen.integers(3)] = 0.0
    else:
        v[:, 0] *= -1
    if len(f) == 0:
        f = faces[:1]
    return kind, encode(v, f, fmt)


# --- byte and text mutations ---------------------------------------------------------

def _bytes(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    kind = rng.choice(("flip", "truncate", "garbage"))
    if kind == "flip":
        out = bytearray(data)
        for _ in range(rng.randint(1, 20)):
            out[rng.randrange(len(out))] = rng.randrange(256)
        return kind, bytes(out)
    if kind == "truncate":
        return kind, data[: rng.randrange(len(data))]
    return kind, data + bytes(rng.randrange(256) for _ in range(rng.randint(1, 300)))


def _stl_binary(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    kind = rng.choice(("count", "solid-header", "float-field"))
    if len(data) < 84:
        return _bytes(data, fmt, rng)
    if kind == "count":
        (n,) = struct.unpack_from("<I", data, 80)
        new = rng.choice((0, max(n - 1, 0), n + 1, 2 ** 32 - 1, n * 1000))
        return kind, data[:80] + struct.pack("<I", new) + data[84:]
    if kind == "solid-header":  # a binary file whose header reads like ASCII STL
        return kind, b"solid fuzz".ljust(80, b" ") + data[80:]
    out = bytearray(data)
    n = (len(data) - 84) // 50
    for _ in range(rng.randint(1, 5)):
        at = 84 + 50 * rng.randrange(max(n, 1)) + 12 + 4 * rng.randrange(9)
        out[at: at + 4] = struct.pack("<f", rng.choice((np.nan, np.inf, 3.4e38, 1e-45, -0.0)))
    return kind, bytes(out)


def _text_numbers(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    spans = [m.span() for m in _NUMBER.finditer(data)]
    if not spans:
        return _bytes(data, fmt, rng)
    out = data
    for span in sorted(rng.sample(spans, min(len(spans), rng.randint(1, 3))), reverse=True):
        out = out[: span[0]] + rng.choice(BAD_NUMBERS).encode() + out[span[1]:]
    return "number", out


def _text_lines(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    lines = data.split(b"\n")
    if len(lines) < 3:
        return _bytes(data, fmt, rng)
    i = rng.randrange(len(lines))
    kind = rng.choice(("delete-line", "duplicate-line", "swap-lines"))
    if kind == "delete-line":
        del lines[i]
    elif kind == "duplicate-line":
        lines.insert(i, lines[i])
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return kind, b"\n".join(lines)


def _obj(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    faces = list(re.finditer(rb"(?m)^f[ \t]+([^\n]*)", data))
    kind = rng.choice(("index", "short-face", "long-face", "mtllib", "no-vertices"))
    if kind == "mtllib":
        return kind, b"mtllib /etc/passwd\nusemtl x\n" + data
    if kind == "no-vertices":
        return kind, re.sub(rb"(?m)^v[ \t][^\n]*\n", b"", data)
    if not faces:
        return _bytes(data, fmt, rng)
    m = rng.choice(faces)
    if kind == "index":
        new = rng.choice((b"0", b"-999999", b"999999999", b"9223372036854775808", b"1/1/1",
                          b"-1", b"x"))
        idx = list(re.finditer(rb"[^\s/]+", m.group(1)))
        one = rng.choice(idx)
        start = m.start(1) + one.start()
        return kind, data[:start] + new + data[start + len(one.group()):]
    if kind == "short-face":
        return kind, data[: m.start(1)] + b"1 2" + data[m.end(1):]
    corners = " ".join(str(1 + (i % 3)) for i in range(rng.choice((4, 100, 5000))))
    return kind, data[: m.start(1)] + corners.encode() + data[m.end(1):]


_UNIT = re.compile(rb"<unit\b[^>]*?/>")


def _dae_text(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    kind = rng.choice(("unit", "unit", "unit", "float", "count", "index", "node-transform",
                       "instances", "emission-texture", "entity", "delete-element"))
    if kind == "unit":
        value = rng.choice((b"0", b"-1", b"nan", b"inf", b"1e308", b"1e-300", b"", b"abc",
                            b"0.001", b"1e-9", b"1e9"))
        unit = b'<unit name="fuzz" meter="' + value + b'"/>'
        if _UNIT.search(data):
            return f"unit-{value.decode()}", _UNIT.sub(unit, data, count=1)
        return f"unit-{value.decode()}", data.replace(b"<asset>", b"<asset>" + unit, 1)
    if kind == "float":
        arrays = list(re.finditer(rb"<float_array[^>]*>([^<]*)</float_array>", data))
        if not arrays:
            return _text_numbers(data, fmt, rng)
        m = rng.choice(arrays)
        nums = list(_NUMBER.finditer(m.group(1)))
        if not nums:
            return _text_numbers(data, fmt, rng)
        one = rng.choice(nums)
        start = m.start(1) + one.start()
        new = rng.choice((b"nan", b"NaN", b"inf", b"-inf", b"1e308", b"1e39", b"1e-46"))
        return "float-" + new.decode(), data[:start] + new + data[start + len(one.group()):]
    if kind == "count":
        counts = list(re.finditer(rb"\bcount=\"(\d+)\"", data))
        if not counts:
            return _text_numbers(data, fmt, rng)
        m = rng.choice(counts)
        new = rng.choice((b"0", b"1", b"999999999", b"-1", str(int(m.group(1)) + 1).encode()))
        return kind, data[: m.start(1)] + new + data[m.end(1):]
    if kind == "index":
        ps = list(re.finditer(rb"<p>([^<]*)</p>", data))
        if not ps:
            return _text_numbers(data, fmt, rng)
        m = rng.choice(ps)
        nums = list(re.finditer(rb"\d+", m.group(1)))
        if not nums:
            return _text_numbers(data, fmt, rng)
        one = rng.choice(nums)
        start = m.start(1) + one.start()
        new = rng.choice((b"99999999", b"-1", b"4294967296"))
        return kind, data[:start] + new + data[start + len(one.group()):]
    if kind == "node-transform":
        value = rng.choice((b"<scale>0 0 0</scale>", b"<scale>1e308 1 1</scale>",
                            b"<matrix>nan 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>",
                            b"<matrix>0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1</matrix>",
                            b"<scale>-1 1 1</scale>"))
        m = re.search(rb"<node\b[^>]*>", data)
        if not m:
            return _text_numbers(data, fmt, rng)
        return kind, data[: m.end()] + value + data[m.end():]
    if kind == "instances":
        m = re.search(rb"<instance_geometry\b.*?(?:/>|</instance_geometry>)", data, re.S)
        if not m:
            return _text_numbers(data, fmt, rng)
        copies = rng.choice((2, 100, 5000))
        return kind, data[: m.end()] + m.group() * copies + data[m.end():]
    if kind == "emission-texture":
        return kind, _with_emission_texture(data)
    if kind == "entity":
        decl = (b'<!DOCTYPE COLLADA [<!ENTITY a "aaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;">]>'
                if rng.random() < 0.5 else
                b'<!DOCTYPE COLLADA [<!ENTITY x SYSTEM "file:///etc/passwd">]>')
        end = data.find(b"?>") + 2 if data.startswith(b"<?xml") else 0
        return kind, data[:end] + b"\n" + decl + data[end:]
    tags = (b"triangles", b"input", b"source", b"vertices", b"node", b"scene", b"p",
            b"accessor", b"float_array", b"visual_scene", b"instance_geometry")
    tag = rng.choice(tags)
    found = list(re.finditer(rb"<" + tag + rb"\b(?:[^>]*?/>|.*?</" + tag + rb">)", data, re.S))
    if not found:
        return _text_lines(data, fmt, rng)
    m = rng.choice(found)
    return f"delete-{tag.decode()}", data[: m.start()] + data[m.end():]


def _with_emission_texture(data: bytes) -> bytes:
    """The document with one more material, whose emission is a texture map: trimesh's
    material parser logs a warning with a traceback for it (what PR2's COLLADA files do)."""
    return data.replace(b"<library_geometries", EMISSION_LIBRARIES + b"<library_geometries", 1)


#: COLLADA libraries of an image, an effect with a texture as its emission and a material.
EMISSION_LIBRARIES = (
    b'<library_images><image id="fuzzimg"><init_from>missing.png</init_from></image>'
    b'</library_images><library_effects><effect id="fuzzfx"><profile_COMMON>'
    b'<newparam sid="surf"><surface type="2D"><init_from>fuzzimg</init_from></surface>'
    b'</newparam><newparam sid="samp"><sampler2D><source>surf</source></sampler2D>'
    b'</newparam><technique sid="common"><phong><emission><texture texture="samp" '
    b'texcoord="UV"/></emission><diffuse><texture texture="samp" texcoord="UV"/>'
    b'</diffuse></phong></technique></profile_COMMON></effect></library_effects>'
    b'<library_materials><material id="fuzzmat"><instance_effect url="#fuzzfx"/>'
    b'</material></library_materials>')


def _ply(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    m = re.search(rb"element (vertex|face) (\d+)", data)
    kind = rng.choice(("count", "format", "index"))
    if kind == "count" and m:
        new = rng.choice((b"0", b"999999999", b"18446744073709551616", b"-1",
                          str(int(m.group(2)) + 1).encode()))
        return f"count-{m.group(1).decode()}", data[: m.start(2)] + new + data[m.end(2):]
    if kind == "format":
        new = rng.choice((b"format ascii 1.0", b"format binary_big_endian 1.0",
                          b"format binary_little_endian 2.0"))
        return kind, re.sub(rb"format [^\n]*", new, data, count=1)
    head = data.find(b"end_header\n") + len(b"end_header\n")
    vcount = re.search(rb"element vertex (\d+)", data)
    fcount = re.search(rb"element face (\d+)", data)
    if head < 11 or not vcount or not fcount:
        return _bytes(data, fmt, rng)
    start = head + 12 * int(vcount.group(1))
    nf = int(fcount.group(1))
    if nf == 0:
        return _bytes(data, fmt, rng)
    out = bytearray(data)
    at = start + 13 * rng.randrange(nf) + 1 + 4 * rng.randrange(3)
    out[at: at + 4] = struct.pack("<i", rng.choice((-1, 2 ** 31 - 1, 10 ** 8)))
    return "index", bytes(out)


def _glb_json(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    found = unpack_glb(data)
    if found is None:
        return _bytes(data, fmt, rng)
    doc, binary = found
    kind = rng.choice(("accessor-count", "node-scale", "node-matrix", "byte-length",
                       "mode", "buffer-uri", "indices-float", "many-nodes"))
    acc = doc.get("accessors") or [{}]
    nodes = doc.setdefault("nodes", [{}])
    if kind == "accessor-count":
        rng.choice(acc)["count"] = rng.choice((0, 10 ** 9, -1, 2 ** 40))
    elif kind == "node-scale":
        nodes[0]["scale"] = rng.choice(([0, 0, 0], [1e308, 1, 1], [-1, 1, 1]))
    elif kind == "node-matrix":
        nodes[0]["matrix"] = rng.choice(([float("nan")] + [0.0] * 15,
                                         [0.0] * 15 + [1.0], [1e300] * 16))
    elif kind == "byte-length":
        for view in doc.get("bufferViews", []):
            view["byteLength"] = rng.choice((0, 10 ** 12, view.get("byteLength", 0) * 2))
    elif kind == "mode":
        for mesh in doc.get("meshes", []):
            for prim in mesh.get("primitives", []):
                prim["mode"] = rng.choice((0, 1, 3, 5, 6, 99))
    elif kind == "buffer-uri":
        doc["buffers"] = [{"byteLength": 10 ** 6, "uri": rng.choice(
            ("/etc/passwd", "../../../../etc/passwd", "http://127.0.0.1:9/b.bin",
             "data:application/octet-stream;base64,AAAA"))}]
    elif kind == "indices-float":
        for mesh in doc.get("meshes", []):
            for prim in mesh.get("primitives", []):
                prim["indices"] = 0
    else:
        count = rng.choice((100, 20000))
        doc["nodes"] = [{"mesh": 0} for _ in range(count)]
        doc["scenes"] = [{"nodes": list(range(count))}]
    return kind, pack_glb(doc, binary)


#: Format-specific mutators besides the geometric and byte ones.
_SPECIFIC = {
    "stl": (_stl_binary,),
    "stl-ascii": (_text_numbers, _text_lines),
    "obj": (_obj, _text_numbers, _text_lines),
    "dae": (_dae_text, _dae_text, _text_numbers),
    "ply": (_ply,),
    "glb": (_glb_json,),
}


def mutate_mesh(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    """One mutation of a ``fmt`` mesh file."""
    group = rng.choices(("geometric", "specific", "bytes"), (5, 4, 1))[0]
    if group == "geometric":
        return _geometric(data, fmt, rng)
    if group == "specific":
        return rng.choice(_SPECIFIC[fmt])(data, fmt, rng)
    return _bytes(data, fmt, rng)
