"""Returning freed memory to the system between the meshes of a worker."""

from __future__ import annotations

import sys

import pytest

from urdfinertia.batch import heap, tasks
from urdfinertia.cache import library as meshlib


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's malloc_trim")
def test_release_free_memory_trims_on_glibc():
    import platform

    if platform.libc_ver()[0] != "glibc":
        pytest.skip("not a glibc system")
    assert heap.release_free_memory(above=None) is True


def test_release_free_memory_is_a_no_op_without_malloc_trim(monkeypatch):
    monkeypatch.setattr(heap, "_TRIM", False)  # looked up before and not found
    assert heap.release_free_memory() is False


def test_release_free_memory_survives_a_failing_call(monkeypatch):
    def failing(pad: int) -> int:
        raise OSError("no")

    monkeypatch.setattr(heap, "_TRIM", failing)
    assert heap.release_free_memory(above=None) is False


def test_release_free_memory_trims_only_above_the_resident_size(monkeypatch):
    calls: list[int] = []
    monkeypatch.setattr(heap, "_TRIM", lambda pad: calls.append(pad) or 1)
    resident = heap.resident_bytes()
    if resident is None:
        pytest.skip("no /proc/self/statm")
    assert resident > 10 * 2**20  # a Python process with numpy holds more than this
    assert heap.release_free_memory(above=resident * 4) is False and calls == []
    assert heap.release_free_memory(above=resident // 4) is True and calls == [0]
    assert heap.release_free_memory(above=None) is True and calls == [0, 0]


def test_mesh_task_releases_memory_before_each_mesh(tmp_path, monkeypatch):
    import trimesh

    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=(0.1, 0.2, 0.3)).export(path)
    events: list[str] = []
    real = meshlib.load_mesh
    monkeypatch.setattr(heap, "release_free_memory", lambda: events.append("release") or True)
    monkeypatch.setattr(meshlib, "load_mesh", lambda p, m: events.append("read") or real(p, m))
    for _ in range(2):
        solids, faces, _, points, _ = tasks.mesh_task(str(path), 1000)
        assert not isinstance(solids, Exception) and faces == 12 and points is not None
    assert events == ["release", "read", "release", "read"]
