"""MeshLibrary: each file read once, cache hits equal to computed results, stage times."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from urdfinertia.cache import library as meshlib
from urdfinertia.cache.library import MeshLibrary, mesh_file_solids
from urdfinertia.cache.store import SolidsCache
from urdfinertia.errors import MeshError
from urdfinertia.mesh.read.load import load_mesh
from urdfinertia.mesh.solids import mesh_solids


@pytest.fixture
def box_stl(tmp_path):
    path = tmp_path / "box.stl"
    mesh = trimesh.creation.box(extents=(0.2, 0.1, 0.05))
    mesh.apply_translation((0.3, -0.1, 0.05))
    mesh.export(path)
    return path


@pytest.fixture
def count_reads(monkeypatch):
    calls: list[str] = []
    real = meshlib.load_mesh

    def counting(path, max_faces):
        calls.append(str(path))
        return real(path, max_faces)

    monkeypatch.setattr(meshlib, "load_mesh", counting)
    return calls


def test_a_file_is_read_once_per_library(box_stl, count_reads):
    lib = MeshLibrary()
    a = lib.solids(box_stl)
    b = lib.solids(box_stl.parent / "." / box_stl.name)  # another spelling, same file
    assert a is b
    assert len(count_reads) == 1


def test_results_equal_the_plain_computation(box_stl):
    direct = mesh_solids(load_mesh(box_stl))
    found = MeshLibrary().solids(box_stl)
    assert found.solids[0].volume == direct.solids[0].volume
    np.testing.assert_array_equal(found.solids[0].second, direct.solids[0].second)
    # rel 1e-6: STL stores float32 coordinates
    assert found.solids[0].volume == pytest.approx(0.2 * 0.1 * 0.05, rel=1e-6)


def test_cache_hit_is_identical_and_skips_reading(box_stl, tmp_path, count_reads):
    store = SolidsCache(tmp_path / "cache")
    cold = MeshLibrary(cache=store).solids(box_stl)
    warm = MeshLibrary(cache=store).solids(box_stl)
    assert len(count_reads) == 1
    assert store.hits == 1
    for x, y in zip(cold.solids, warm.solids, strict=True):
        assert x.volume == y.volume
        np.testing.assert_array_equal(x.first, y.first)
        np.testing.assert_array_equal(x.second, y.second)
        assert (x.method, x.notes) == (y.method, y.notes)
    assert cold.notes == warm.notes


def test_scale_is_applied_after_the_cache(box_stl, tmp_path):
    """Volume scales by |det S|, second moments by S S^T (mirroring included)."""
    store = SolidsCache(tmp_path / "cache")
    scale = np.array([2.0, -0.5, 3.0])
    MeshLibrary(cache=store).solids(box_stl)
    scaled = MeshLibrary(cache=store).solids(box_stl).scaled(scale).solids[0]
    mesh = load_mesh(box_stl)
    direct = mesh_solids(type(mesh)(mesh.vertices * scale, mesh.faces[:, ::-1])).solids[0]
    # rel 1e-12: same integrals, rounding differs only in the last bits
    assert scaled.volume == pytest.approx(direct.volume, rel=1e-12)
    np.testing.assert_allclose(scaled.first, direct.first, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(scaled.second, direct.second, rtol=1e-12, atol=1e-18)


def test_face_limit_holds_on_a_cache_hit(box_stl, tmp_path):
    store = SolidsCache(tmp_path / "cache")
    mesh_file_solids(box_stl, 1000, store)
    with pytest.raises(MeshError) as uncached:
        mesh_file_solids(box_stl, 5)
    with pytest.raises(MeshError) as cached:
        mesh_file_solids(box_stl, 5, store)
    assert store.hits == 1
    assert str(cached.value) == str(uncached.value)


def test_a_failing_mesh_fails_once_and_repeats_a_fresh_error(tmp_path, count_reads):
    bad = tmp_path / "bad.stl"
    bad.write_bytes(b"solid x\nfacet normal 0 0 1\nnot really\n")
    lib = MeshLibrary()
    with pytest.raises(MeshError) as first:
        lib.solids(bad)
    first.value.with_context(link="left_leg")
    with pytest.raises(MeshError) as second:
        lib.solids(bad)
    assert len(count_reads) == 1
    assert second.value is not first.value
    assert second.value.link is None  # context added to one report stays there
    assert str(bad) in second.value.cause and second.value.file is None  # file = the URDF


def test_stage_times_are_recorded(box_stl, tmp_path):
    lib = MeshLibrary(cache=SolidsCache(tmp_path / "cache"))
    lib.solids(box_stl)
    stages = set(lib.timer.seconds)
    assert {"mesh read", "repair", "cache"} <= stages
    assert all(v >= 0 for v in lib.timer.seconds.values())


def test_seeded_results_are_used_without_reading(box_stl, count_reads):
    computed = MeshLibrary().solids(box_stl)
    lib = MeshLibrary()
    lib.seed(box_stl, computed)
    assert lib.solids(box_stl) is computed
    assert len(count_reads) == 1


def test_a_rejected_mesh_is_remembered_by_the_cache(tmp_path, count_reads):
    flat = tmp_path / "flat.stl"
    trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
                    [[0, 1, 2], [0, 2, 3]]).export(flat)
    store = SolidsCache(tmp_path / "cache")
    with pytest.raises(MeshError) as cold:
        MeshLibrary(cache=store).solids(flat)
    with pytest.raises(MeshError) as warm:
        MeshLibrary(cache=store).solids(flat)
    assert len(count_reads) == 1
    assert str(warm.value) == str(cold.value)


# --- points for bounding boxes (check's geometry), kept in the persistent cache ---------
@pytest.fixture
def sphere_stl(tmp_path):
    path = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(3, 0.2).export(path)  # 642 vertices, most not on a box
    return path


def test_points_give_the_boxes_of_every_vertex_under_any_rotation(sphere_stl, rng):
    from scipy.spatial.transform import Rotation

    mesh = load_mesh(sphere_stl)
    every = mesh.vertices[np.unique(mesh.faces)]
    points = MeshLibrary().points(sphere_stl)
    assert len(points) <= len(every)
    for r in Rotation.random(20, random_state=7).as_matrix():
        scale = rng.uniform(-2.0, 2.0, size=3)  # mirrored too
        a, b = (every * scale) @ r.T, (points * scale) @ r.T
        # the hull's vertices hold every extreme: the same boxes to round-off (1e-15 m:
        # a point on a hull facet may round one unit above its vertices)
        np.testing.assert_allclose(a.min(axis=0), b.min(axis=0), rtol=0, atol=1e-15)
        np.testing.assert_allclose(a.max(axis=0), b.max(axis=0), rtol=0, atol=1e-15)


def test_points_come_from_the_cache_on_a_second_run(sphere_stl, tmp_path, count_reads):
    first = MeshLibrary(cache=SolidsCache(tmp_path / "cache")).points(sphere_stl)
    assert len(count_reads) == 1
    again = MeshLibrary(cache=SolidsCache(tmp_path / "cache")).points(sphere_stl)
    assert len(count_reads) == 1  # no mesh file read
    np.testing.assert_array_equal(first, again)
    with pytest.raises(MeshError, match="faces"):  # the face limit holds on a hit too
        MeshLibrary(max_faces=10, cache=SolidsCache(tmp_path / "cache")).points(sphere_stl)


def test_flat_meshes_keep_all_their_points(tmp_path):
    flat = np.c_[np.random.default_rng(1).uniform(size=(100, 2)), np.zeros(100)]
    assert len(meshlib.hull_points(flat)) == 100


def test_every_command_reads_and_fills_the_one_cache(sphere_stl, tmp_path, count_reads,
                                                     monkeypatch):
    """check, compare, explain and report build their libraries with mesh_library: what
    one of them computed, the next reads from the cache (the suite's private cache dir)."""
    from urdfinertia.cli import main

    urdf = tmp_path / "ball.urdf"
    urdf.write_text(f"""<robot name="ball"><link name="ball">
  <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
  </inertial>
  <collision><geometry><mesh filename="{sphere_stl.name}"/></geometry></collision>
</link></robot>""")
    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(tmp_path / "shared-cache"))
    # -j 1: check and report compute in this process, where the reads are counted
    main(["check", str(urdf), "-q", "-j", "1"])
    assert count_reads  # the first command reads the mesh
    count_reads.clear()
    main(["check", str(urdf), "-q", "-j", "1"])
    main(["compare", str(urdf)])
    assert main(["explain", str(urdf), "--link", "ball"]) == 0
    assert count_reads == []  # nothing read again: points and solids came from the cache
    assert main(["report", str(urdf), "-o", str(tmp_path / "r.html"), "-j", "1"]) == 0
    assert len(count_reads) == 1  # the display copy, made once
    assert main(["report", str(urdf), "-o", str(tmp_path / "r2.html"), "-j", "1"]) == 0
    assert len(count_reads) == 1  # and then read from the cache
    assert (tmp_path / "r.html").read_bytes() == (tmp_path / "r2.html").read_bytes()


def test_mesh_library_without_cache(tmp_path):
    assert meshlib.mesh_library(use_cache=False).cache is None
    lib = meshlib.mesh_library(cache_dir=tmp_path / "c")
    assert lib.cache is not None and lib.cache.root == tmp_path / "c"


def test_points_then_solids_read_the_file_once(sphere_stl, count_reads):
    """The geometry checks ask for a mesh's points, then for its solids: one reading."""
    lib = MeshLibrary()
    points = lib.points(sphere_stl)
    solids = lib.solids(sphere_stl)
    assert len(count_reads) == 1
    np.testing.assert_array_equal(points, MeshLibrary().points(sphere_stl))
    assert solids.solids[0].volume == MeshLibrary().solids(sphere_stl).solids[0].volume


def test_the_stash_of_read_meshes_is_bounded(sphere_stl, tmp_path, count_reads, monkeypatch):
    monkeypatch.setattr(meshlib, "STASH_FACES", 1500)  # one 1,280-face sphere at a time
    other = tmp_path / "other.stl"
    trimesh.creation.icosphere(3, 0.3).export(other)
    lib = MeshLibrary()
    lib.points(sphere_stl)
    lib.points(other)  # evicts the first
    lib.solids(other)
    lib.solids(sphere_stl)
    assert [Path(p).name for p in count_reads] == ["sphere.stl", "other.stl", "sphere.stl"]
    assert sum(len(m.faces) for m in lib._stash.values()) <= 1500


def test_seeded_points_are_not_computed_again(sphere_stl, count_reads):
    points = MeshLibrary().points(sphere_stl)
    lib = MeshLibrary()
    lib.seed_points(sphere_stl, points)
    np.testing.assert_array_equal(lib.points(sphere_stl), points)
    assert len(count_reads) == 1


def test_hull_volume_is_the_scaled_hulls_and_computed_once(box_stl, monkeypatch):
    """The geometry choice asks a mesh's hull volume per link and candidate: memoised."""
    from scipy import spatial

    calls = []
    real = spatial.ConvexHull

    def counting(points, *args, **kwargs):
        calls.append(len(points))
        return real(points, *args, **kwargs)

    monkeypatch.setattr(spatial, "ConvexHull", counting)
    lib = MeshLibrary()
    box = trimesh.load(box_stl, force="mesh")
    for scale in [(1.0, 1.0, 1.0), (2.0, 1.0, 0.5), (1.0, 1.0, 1.0), (2.0, -1.0, 0.5)]:
        assert lib.hull_volume(box_stl, scale) == pytest.approx(
            box.convex_hull.volume * abs(np.prod(scale)), rel=1e-12)
    assert len(calls) == 1  # one hull per mesh: a scale multiplies its volume


def test_the_hull_volume_is_cached_with_the_points(sphere_stl, tmp_path, monkeypatch, rng):
    """A warm library takes the hull's volume from the points' cache entry: no Qhull. Per
    scale it equals the hull of the scaled points up to round-off (the map is linear)."""
    from scipy import spatial

    scales = [(1.0, 1.0, 1.0), (0.001, 0.001, 0.001), (2.0, -1.0, 0.5),
              *(tuple(x) for x in rng.uniform(-3, 3, size=(5, 3)))]
    cold = MeshLibrary(cache=SolidsCache(tmp_path / "c"))
    volumes = [cold.hull_volume(sphere_stl, s) for s in scales]
    points = cold.points(sphere_stl)
    for scale, volume in zip(scales, volumes, strict=True):
        direct = spatial.ConvexHull(points * np.asarray(scale)).volume
        assert volume == pytest.approx(direct, rel=1e-13)

    def no_qhull(*args, **kwargs):
        raise AssertionError("Qhull ran on a warm library")

    monkeypatch.setattr(spatial, "ConvexHull", no_qhull)
    warm = MeshLibrary(cache=SolidsCache(tmp_path / "c"))
    assert [warm.hull_volume(sphere_stl, s) for s in scales] == volumes
    seeded = MeshLibrary()
    header, _ = SolidsCache(tmp_path / "c").lookup_arrays(sphere_stl, seeded.max_faces,
                                                          "points")[1]
    seeded.seed_points(sphere_stl, points, header)
    assert seeded.hull_volume(sphere_stl, scales[2]) == volumes[2]


def test_flat_points_have_no_hull_volume(tmp_path):
    flat = tmp_path / "flat.stl"
    trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
                    [[0, 1, 2], [1, 3, 2]]).export(flat)
    lib = MeshLibrary(cache=SolidsCache(tmp_path / "c"))
    with pytest.raises(ValueError, match="no volume"):
        lib.hull_volume(flat)
    with pytest.raises(ValueError, match="no volume"):  # from the cache alike
        MeshLibrary(cache=SolidsCache(tmp_path / "c")).hull_volume(flat)


def test_a_display_copy_made_elsewhere_is_the_one_display_makes(sphere_stl, tmp_path,
                                                                 count_reads):
    """seed_display stores what display_entry made in another process; display then reads
    it from the cache, equal to what it would have made itself."""
    from urdfinertia.render.scene import decimate

    cache = SolidsCache(tmp_path / "cache")
    lib = MeshLibrary(cache=cache)
    assert not lib.display_cached(sphere_stl, 100)
    made = meshlib.display_entry(load_mesh(sphere_stl, 10**6), 100, decimate)
    lib.seed_display(sphere_stl, 100, *made)
    assert lib.display_cached(sphere_stl, 100)
    assert not lib.display_cached(sphere_stl, 101)  # per face cap
    count_reads.clear()
    v, f, faces, how = lib.display(sphere_stl, 100, decimate)
    assert count_reads == []  # from the cache
    ref_v, ref_f, ref_faces, ref_how = MeshLibrary().display(sphere_stl, 100, decimate)
    np.testing.assert_array_equal(v, ref_v)
    np.testing.assert_array_equal(f, ref_f)
    assert (faces, how) == (ref_faces, ref_how) and len(f) <= 150 < faces


def test_seeding_a_display_copy_needs_a_cache_and_a_valid_entry(sphere_stl, tmp_path):
    from urdfinertia.render.scene import decimate

    made = meshlib.display_entry(load_mesh(sphere_stl, 10**6), 100, decimate)
    MeshLibrary().seed_display(sphere_stl, 100, *made)  # no cache: nothing, no error
    lib = MeshLibrary(cache=SolidsCache(tmp_path / "cache"))
    header, numbers = made
    bad = numbers.copy()
    bad[-1] = header["vertices"]  # a face index past the vertices
    lib.seed_display(sphere_stl, 100, header, bad)
    assert not lib.display_cached(sphere_stl, 100)


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_warm_check_runs_no_qhull(sphere_stl, tmp_path, monkeypatch, jobs):
    """The second ``check`` of a link judged between a collision and a visual mesh takes
    every hull (its points and its volume) from the cache, with or without workers."""
    from scipy import spatial

    from urdfinertia.cli import main

    urdf = tmp_path / "two.urdf"
    urdf.write_text(f"""<robot name="two"><link name="l">
  <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
  </inertial>
  <visual><geometry><mesh filename="{sphere_stl.name}" scale="2 2 2"/></geometry></visual>
  <collision><geometry><mesh filename="{sphere_stl.name}"/></geometry></collision>
</link></robot>""")
    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(tmp_path / "cache"))
    hulls: list = []
    real = MeshLibrary.hull_volume
    monkeypatch.setattr(MeshLibrary, "hull_volume",
                        lambda self, *a: hulls.append(a) or real(self, *a))
    first = main(["check", str(urdf), "-q", "-j", jobs, "--json", str(tmp_path / "1.json")])
    assert hulls  # the choice weighed the hulls

    def no_qhull(*args, **kwargs):
        raise AssertionError("Qhull ran in a warm check")

    monkeypatch.setattr(spatial, "ConvexHull", no_qhull)
    hulls.clear()
    assert main(["check", str(urdf), "-q", "-j", jobs, "--json",
                 str(tmp_path / "2.json")]) == first
    assert hulls
    assert (tmp_path / "1.json").read_bytes() == (tmp_path / "2.json").read_bytes()


def test_a_mesh_that_runs_out_of_memory_is_its_own_error_with_its_path(box_stl, tmp_path,
                                                                       monkeypatch, capsys):
    """Found by fuzzing: a 12,000-triangle soup ran the repair out of memory, and the run
    ended with "out of memory" naming no file. It is now that mesh's error (the link is
    left, the rest is done), not cached: another machine may have the memory."""
    from urdfinertia import cli

    def exhausted(mesh, timer=None, seconds=-1.0):
        raise MemoryError

    monkeypatch.setattr(meshlib, "repair_mesh", exhausted)
    cache = SolidsCache(tmp_path / "cache")
    with pytest.raises(MeshError, match="out of memory repairing") as found:
        mesh_file_solids(box_stl, cache=cache)
    assert str(box_stl) in found.value.cause and not found.value.of_bytes
    robot = tmp_path / "r.urdf"
    robot.write_text('<robot name="r"><link name="a"/><link name="b"><collision><geometry>'
                     f'<mesh filename="{box_stl}"/></geometry></collision></link>'
                     '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
                     '<limit effort="1" velocity="1"/></joint></robot>')
    code = cli.main(["fix", str(robot), "-o", str(tmp_path / "out.urdf"), "-q", "--no-cache"])
    err = capsys.readouterr().err
    assert code == 1, err
    assert f"{box_stl}: out of memory" in err and "link 'b'" in err
