"""Damaged cache entries and digest memo between two runs of `fix`: never trusted.

Each damage is one a fault injection found making `fix` write wrong values silently (or
hang): the second and third runs must write what a run without a cache writes.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.cache.store import DIGESTS_FILE, MAGIC
from urdfinertia.cli import main

SEAL_BYTES = 32  # the BLAKE2b seal that ends an entry (cache.store.SEAL_BYTES)

DATA = Path(__file__).parents[1] / "data" / "broken"


@pytest.fixture
def robot(tmp_path) -> Path:
    folder = tmp_path / "robot"
    folder.mkdir()
    shutil.copy(DATA / "cube.stl", folder / "cube.stl")
    # a second mesh, three times as long in x, so entries and digests can be swapped
    cube = (DATA / "cube.stl").read_text(encoding="utf-8")
    (folder / "long.stl").write_text(re.sub(
        r"vertex (\S+)", lambda m: f"vertex {3 * float(m[1])}", cube), encoding="utf-8")
    urdf = (DATA / "clean.urdf").read_text(encoding="utf-8")
    urdf = urdf.replace('<sphere radius="0.04"/>', '<mesh filename="long.stl"/>')
    (folder / "robot.urdf").write_text(urdf, encoding="utf-8")
    return folder / "robot.urdf"


def fix(robot: Path, out: Path, *cache: str) -> str:
    assert main(["fix", str(robot), "-o", str(out), "--all", "-q", *cache]) == 0
    return out.read_text(encoding="utf-8")


def entries(root: Path) -> list[Path]:
    found = sorted(root.rglob("*.entry"))
    assert found, "the first run stored nothing"
    return found


def flip(path: Path, at: int, count: int) -> None:
    data = bytearray(path.read_bytes())
    at = min(at, len(data) - count)
    for i in range(at, at + count):
        data[i] ^= 0xFF
    path.write_bytes(bytes(data))


def scale_volumes(path: Path) -> None:
    """Every volume of a solids entry times 1.5, in place (the numbers still valid)."""
    data = path.read_bytes()
    if not data.startswith(MAGIC):
        return
    pos = len(MAGIC)
    size = int.from_bytes(data[pos:pos + 4], "little")
    header = json.loads(data[pos + 4:pos + 4 + size])
    if "solids" not in header:
        return
    start = pos + 4 + size
    k = len(header["solids"])
    volumes = np.frombuffer(data[start:start + 8 * k], dtype="<f8") * 1.5
    path.write_bytes(data[:start] + volumes.astype("<f8").tobytes() + data[start + 8 * k:])


def damage(root: Path, kind: str) -> None:
    found = entries(root)
    if kind == "eight bytes":
        for path in found:
            flip(path, path.stat().st_size // 2, 8)
    elif kind == "payload bit":
        for path in found:
            flip(path, path.stat().st_size - SEAL_BYTES - 9, 1)
    elif kind == "volumes x1.5":
        for path in found:
            scale_volumes(path)
    elif kind == "entries permuted":
        contents = [p.read_bytes() for p in found]
        for path, data in zip(found, contents[1:] + contents[:1], strict=True):
            path.write_bytes(data)
    elif kind == "digests permuted":
        memo = root / DIGESTS_FILE
        doc = json.loads(memo.read_text(encoding="utf-8"))
        records = list(doc["files"].values())
        assert len(records) == 2
        # each mesh file now names the other's content (whose entry is valid)
        records[0][5], records[1][5] = records[1][5], records[0][5]
        memo.write_text(json.dumps(doc), encoding="utf-8")
    elif kind == "fifo":
        for path in found:
            path.unlink()
            os.mkfifo(path)
    elif kind == "link to /dev/zero":
        for path in found:
            path.unlink()
            path.symlink_to("/dev/zero")
    else:
        raise AssertionError(kind)


KINDS = ["eight bytes", "payload bit", "volumes x1.5", "entries permuted",
         "digests permuted", "fifo", "link to /dev/zero"]


@pytest.mark.parametrize("kind", KINDS)
def test_damaged_cache_never_changes_the_output(robot, tmp_path, kind, monkeypatch):
    from urdfinertia.cache import digests

    monkeypatch.setattr(digests, "RACY_SECONDS", 0.0)  # remember the fresh meshes' digests
    clean = fix(robot, tmp_path / "clean.urdf", "--no-cache")
    cache = ["--cache-dir", str(tmp_path / "cache")]
    assert fix(robot, tmp_path / "cold.urdf", *cache) == clean
    damage(tmp_path / "cache", kind)
    # a subprocess with a timeout: a FIFO entry opened for reading would block forever
    argv = [sys.executable, "-m", "urdfinertia", "fix", str(robot), "-o",
            str(tmp_path / "damaged.urdf"), "--all", "-q", *cache]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "damaged.urdf").read_text(encoding="utf-8") == clean
    # the bad entries were replaced, not kept: the next run reads good ones
    assert fix(robot, tmp_path / "again.urdf", *cache) == clean
    for path in entries(tmp_path / "cache"):
        assert path.is_file() and not path.is_symlink()
