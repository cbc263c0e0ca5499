"""Fuzz ``urdf-inertia fix`` with mutated valid URDFs: only documented outcomes happen.

Each case mutates a small valid URDF (byte flips, truncation, deleted attributes, swapped
tags, huge or tiny numbers, duplicated elements) and runs the CLI in-process. Allowed
outcomes with ``--strict``: exit 0 with an output that reads back as a URDF, or exit 2 with
one line on stderr; without it, also exit 1 (written, some links left as they were).
Never an internal error (exit 3), a traceback, a changed input or a stray file.
The cases come from a fixed seed, so a failure names a reproducible case id.
"""

from __future__ import annotations

import random
import re
import struct
from pathlib import Path

import numpy as np
import pytest

from urdfinertia import cli
from urdfinertia.descriptions.urdf.read import read_urdf

SEED = 20240611
CASES = 240

BASE = """<?xml version="1.0"?>
<robot name="fuzz">
  <link name="base">
    <inertial>
      <origin xyz="0.01 0 0" rpy="0 0 0"/>
      <mass value="2"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
    <collision>
      <origin xyz="0 0 0.1" rpy="0 0.3 0"/>
      <geometry><box size="0.1 0.2 0.3"/></geometry>
    </collision>
    <collision>
      <geometry><sphere radius="0.05"/></geometry>
    </collision>
  </link>
  <link name="arm">
    <visual>
      <origin xyz="0 0 0.2" rpy="1.57 0 0"/>
      <geometry><cylinder radius="0.04" length="0.4"/></geometry>
    </visual>
    <collision>
      <geometry><mesh filename="cube.stl" scale="1 2 1"/></geometry>
    </collision>
  </link>
  <link name="tool"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/>
  </joint>
  <joint name="j2" type="fixed"><parent link="arm"/><child link="tool"/></joint>
</robot>
"""

HUGE = ["1e308", "-1e308", "1e-320", "1e400", "9" * 400, "0", "-0", "1e-300", "5e-324",
        "1e30", "-1e30", "1e15", "NaN", "-inf", "", "1,5", "0x10", "1e", "."]
TAGS = ["link", "joint", "inertial", "collision", "visual", "geometry", "origin", "mass",
        "inertia", "box", "sphere", "cylinder", "mesh", "robot", "capsule", "parent"]


def cube_stl(size: float = 0.1) -> bytes:
    import trimesh

    mesh = trimesh.creation.box((size, size, size))
    tri = mesh.vertices[mesh.faces].astype(np.float32)
    out = bytearray(b"\0" * 80 + struct.pack("<I", len(tri)))
    for t in tri:
        out += struct.pack("<3f", 0, 0, 0) + t.tobytes() + b"\0\0"
    return bytes(out)


def mutate(data: bytes, rng: random.Random) -> tuple[str, bytes]:
    """One random mutation of ``data``; returns its kind (for failure messages)."""
    kind = rng.choice(["flip", "truncate", "delete_attr", "swap_tags", "rename_tag", "number",
                       "duplicate", "splice"])
    if len(data) < 2:
        return "append", data + b"<"
    if kind == "flip":
        return mutate_flip(data, rng)
    if kind == "truncate":
        return kind, data[: rng.randrange(len(data))]
    if kind == "delete_attr":
        spans = [m.span() for m in re.finditer(rb'\s[a-z_]+="[^"]*"', data)]
        if not spans:
            return mutate_flip(data, rng)
        start, end = rng.choice(spans)
        return kind, data[:start] + data[end:]
    if kind == "swap_tags":
        names = [m for m in re.finditer(rb"<(/?)([a-z_]+)", data)]
        if len(names) < 2:
            return mutate_flip(data, rng)
        a, b = rng.sample(names, 2)
        (s1, e1), (s2, e2) = sorted([a.span(2), b.span(2)])
        return kind, data[:s1] + data[s2:e2] + data[e1:s2] + data[s1:e1] + data[e2:]
    if kind == "rename_tag":
        old, new = rng.sample(TAGS, 2)
        return kind, data.replace(f"<{old}".encode(), f"<{new}".encode(), 1)
    if kind == "number":
        spans = [m.span() for m in re.finditer(rb"-?[0-9]+(?:\.[0-9]+)?", data)]
        if not spans:
            return mutate_flip(data, rng)
        start, end = rng.choice(spans)
        return kind, data[:start] + rng.choice(HUGE).encode() + data[end:]
    if kind == "duplicate":
        elems = [m.span() for m in re.finditer(rb"<(link|joint|collision|inertial)\b.*?</\1>",
                                               data, re.DOTALL)]
        if not elems:
            return mutate_flip(data, rng)
        start, end = rng.choice(elems)
        return kind, data[:end] + data[start:end] + data[end:]
    start = rng.randrange(len(data))  # splice: a piece of the document somewhere else
    piece = data[start: start + rng.randint(1, 60)]
    at = rng.randrange(len(data))
    return kind, data[:at] + piece + data[at:]


def mutate_flip(data: bytes, rng: random.Random) -> tuple[str, bytes]:
    out = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        out[rng.randrange(len(out))] = rng.randrange(256)
    return "flip", bytes(out)


def cases() -> list[tuple[int, str, bytes]]:
    rng = random.Random(SEED)
    base = BASE.encode()
    out = []
    for i in range(CASES):
        data = base
        kinds = []
        for _ in range(rng.choice([1, 1, 1, 2, 3])):
            kind, data = mutate(data, rng)
            kinds.append(kind)
        out.append((i, "+".join(kinds), data))
    return out


@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("fuzz")
    (folder / "cube.stl").write_bytes(cube_stl())
    return folder


def test_base_document_is_valid(fuzz_dir, capsys, monkeypatch):
    """The starting point succeeds, so every failure below comes from the mutation."""
    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(fuzz_dir / "cache"))
    urdf = fuzz_dir / "base.urdf"
    urdf.write_text(BASE)
    assert cli.main(["fix", str(urdf), "-o", str(fuzz_dir / "base.out"), "-q",
                     "--no-cache"]) == 0, capsys.readouterr().err


@pytest.mark.parametrize("strict", [True, False], ids=["strict", "isolating"])
def test_mutated_urdfs_fail_only_with_documented_errors(strict, fuzz_dir, capsys,
                                                         monkeypatch):
    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(fuzz_dir / "cache"))
    outcomes = {0: 0, 1: 0, 2: 0}
    allowed = (0, 2) if strict else (0, 1, 2)
    for i, kinds, data in cases():
        case = fuzz_dir / f"case{i}{'s' if strict else 'i'}"
        case.mkdir()
        (case / "cube.stl").write_bytes((fuzz_dir / "cube.stl").read_bytes())
        urdf = case / "r.urdf"
        urdf.write_bytes(data)
        out = case / "out.urdf"
        code = cli.main(["fix", str(urdf), "-o", str(out), "-q", "--no-cache",
                         *(["--strict"] if strict else [])])
        captured = capsys.readouterr()
        where = f"case {i} ({kinds}): exit {code}: {captured.err!r}"
        assert code in allowed, where
        assert urdf.read_bytes() == data, where
        assert "Traceback" not in captured.err, where
        names = sorted(p.name for p in case.iterdir())
        if code == 2:
            lines = captured.err.splitlines()
            assert len(lines) == 1 and lines[0].startswith("urdf-inertia: error: "), where
            assert names == ["cube.stl", "r.urdf"], where
        else:
            assert names == ["cube.stl", "out.urdf", "r.urdf"], where
            read_urdf(out)  # a successful output is itself a valid URDF
        outcomes[code] += 1
    # the mutations must exercise both outcomes, or the test checks nothing
    assert outcomes[0] > 10 and outcomes[2] > 10, outcomes

