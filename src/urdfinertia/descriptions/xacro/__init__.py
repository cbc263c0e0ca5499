"""xacro: a robot description kept as macros, properties, includes and YAML parameters.

A xacro file is read by expanding it in-process with the `xacro` package
(`.expand`, hardened: every file it reads is checked like a description) and reading
the expanded URDF with the URDF reader; links are named as after expansion. `fix`
patches the expanded URDF (the URDF writer); `fix --write-back` edits the xacro and YAML
sources where each value is written (`.writeback`). Registers the `xacro`
`DescriptionFormat` when imported; it claims a
`<robot>` file ending in `.xacro`, or one whose root declares the xacro namespace and
uses it (a URDF that only keeps the declaration stays a URDF, spliced byte for byte).
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import re
from collections import OrderedDict
from pathlib import Path

from urdfinertia.descriptions.formats import DescriptionFormat, register_format
from urdfinertia.errors import UrdfError

_XACRO_NS = re.compile(rb"xmlns:xacro\s*=\s*[\"']https?://(?:www\.)?ros\.org/wiki/xacro/?[\"']")
_XACRO_USE = re.compile(rb"<xacro:|\$\{|\$\(")
_ROOT_TAG = re.compile(rb"<robot\b[^>]*>", re.S)
_COMMENT = re.compile(rb"<!--.*?-->", re.S)
_MEMO: OrderedDict[tuple, tuple] = OrderedDict()
_MEMO_SIZE = 8


def claims(data: bytes, path: Path) -> bool:
    """A `.xacro` file, or a `<robot>` declaring the xacro namespace and using it."""
    if Path(path).suffix.lower() == ".xacro":
        return True
    head = data[: 1 << 16]
    root = _ROOT_TAG.search(head)
    # generated URDFs often keep the declaration, and xacro code in comments (talos)
    return bool(root and _XACRO_NS.search(root.group(0))
                and _XACRO_USE.search(_COMMENT.sub(b"", data)))


def _signature(paths: tuple[Path, ...]) -> tuple:
    out: list[tuple[str, int | None, int | None]] = []
    for p in paths:
        try:
            st = os.stat(p)
            out.append((str(p), st.st_mtime_ns, st.st_size))
        except OSError:
            out.append((str(p), None, None))
    return tuple(out)


def expansion(data: bytes, path: str | Path):  # noqa: ANN201 - Expansion, imported lazily
    """The expansion of `data` (the file at `path`), memoised while its included files
    are unchanged (the format's read, expand and patch each ask for it)."""
    from urdfinertia.descriptions.xacro.expand import current_settings, expand_xacro

    settings = current_settings()
    key = (os.path.realpath(path), hashlib.blake2b(data, digest_size=20).digest(), settings)
    hit = _MEMO.get(key)
    if hit is not None and _signature(hit[0].sources[1:]) == hit[1]:
        _MEMO.move_to_end(key)
        return hit[0]
    exp = expand_xacro(path, data, settings=settings)
    _MEMO[key] = (exp, _signature(exp.sources[1:]))
    while len(_MEMO) > _MEMO_SIZE:
        _MEMO.popitem(last=False)
    return exp


def _read_with(reader, data: bytes, path: Path):  # noqa: ANN001, ANN202
    from urdfinertia.descriptions.xacro.trace import source_of_line

    exp = expansion(data, path)
    try:
        robot = reader(exp.document, path)
    except UrdfError as exc:  # a line of the expansion means nothing to the user
        where = source_of_line(exp, exc.line) if exc.line is not None else None
        if where is None:
            raise
        raise UrdfError(f"{exc.cause} (after xacro expansion)", file=where[0], line=where[1],
                        link=exc.link) from None
    return dataclasses.replace(robot, format="xacro")


def _read(data, path):  # noqa: ANN001, ANN202 - the format's signature
    from urdfinertia.descriptions.urdf.read import robot_from_bytes

    return _read_with(robot_from_bytes, data, path)


def _expand(data, path):  # noqa: ANN001, ANN202
    return expansion(data, path).document


def _patch(data, new):  # noqa: ANN001, ANN202
    """Patch the expanded URDF (`data` is it, or a xacro source expanded just before)."""
    from urdfinertia.descriptions.urdf.write import patch_inertials

    digest = hashlib.blake2b(data, digest_size=20).digest()
    for key, (exp, _) in reversed(_MEMO.items()):
        if key[1] == digest:  # the source of an expansion made moments ago (batch runs)
            data = exp.document
            break
    else:
        if _XACRO_USE.search(_COMMENT.sub(b"", data)):
            raise UrdfError("xacro source given to the URDF writer without its expansion")
    return patch_inertials(data, new)


def _relocate(data, source_dir, output_dir):  # noqa: ANN001, ANN202
    """What `fix` writes of a xacro file is its expanded URDF: URDF's mesh references."""
    from urdfinertia.descriptions.urdf.mesh_refs import relocate_mesh_refs

    return relocate_mesh_refs(data, source_dir, output_dir)


register_format(DescriptionFormat(
    name="xacro", roots=("robot",), suffixes=(".xacro",),
    read=_read, patch=_patch, claims=claims, expand=_expand,
    relocate=_relocate,
))
