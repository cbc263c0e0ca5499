"""Batch runs: inputs, per-file errors, identical bytes for any --jobs and with a cache."""

from __future__ import annotations

import ast
import concurrent.futures as cf
import contextlib
import os
from pathlib import Path

import pytest
import trimesh

from urdfinertia.batch import run as batch
from urdfinertia.batch.inputs import FileJob, collect_jobs
from urdfinertia.batch.run import BatchSettings, run_batch
from urdfinertia.body.options import FixOptions
from urdfinertia.cache import library as meshlib
from urdfinertia.cli import main
from urdfinertia.errors import OutputError, UrdfError

#: every link recomputed, any element problem fatal: the batch machinery under test
STRICT_ALL = FixOptions(strict=True, recompute="all")


def link(name: str, geometry: str, xyz: str = "0 0 0") -> str:
    return (f'  <link name="{name}"><collision><origin xyz="{xyz}"/>'
            f"<geometry>{geometry}</geometry></collision></link>\n")


def robot(name: str, *links: str) -> str:
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n{"".join(links)}</robot>\n'


@pytest.fixture
def tree(tmp_path) -> Path:
    """pkg_a/{robot_a, sub/robot_b}.urdf sharing meshes; pkg_b/robot_c.urdf primitives only."""
    root = tmp_path / "robots"
    meshes = root / "pkg_a" / "meshes"
    meshes.mkdir(parents=True)
    trimesh.creation.box(extents=(0.2, 0.1, 0.05)).export(meshes / "box.stl")
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(meshes / "ball.stl")
    (root / "pkg_a" / "robot_a.urdf").write_text(robot(
        "a",
        link("base", '<mesh filename="meshes/box.stl"/>'),
        link("left", '<mesh filename="meshes/ball.stl"/>', "0 0.1 0"),
        link("right", '<mesh filename="meshes/ball.stl" scale="1 -1 1"/>', "0 -0.1 0"),
        link("tool", '<box size="0.1 0.1 0.1"/>'),
    ))
    (root / "pkg_a" / "sub").mkdir()
    (root / "pkg_a" / "sub" / "robot_b.urdf").write_text(robot(
        "b", link("body", '<mesh filename="../meshes/box.stl" scale="2 2 2"/>')))
    (root / "pkg_b").mkdir()
    (root / "pkg_b" / "robot_c.urdf").write_text(robot(
        "c", link("rod", '<cylinder radius="0.02" length="0.5"/>')))
    return root


def outputs(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*.urdf"))}


def test_folder_keeps_the_tree(tree, tmp_path):
    jobs = collect_jobs([tree], tmp_path / "out")
    rel = sorted(str(j.output.relative_to(tmp_path / "out")) for j in jobs)
    assert rel == ["pkg_a/robot_a.urdf", "pkg_a/sub/robot_b.urdf", "pkg_b/robot_c.urdf"]


def test_files_go_to_the_output_folder_by_name(tree, tmp_path):
    a = tree / "pkg_a" / "robot_a.urdf"
    jobs = collect_jobs([a, tree / "pkg_b", a], tmp_path / "out")
    assert [j.output for j in jobs] == [tmp_path / "out" / "robot_a.urdf",
                                       tmp_path / "out" / "robot_c.urdf"]


def test_two_inputs_with_one_output_are_refused(tree, tmp_path):
    other = tmp_path / "elsewhere"
    other.mkdir()
    (other / "robot_a.urdf").write_text(robot("x", link("l", '<box size="1 1 1"/>')))
    with pytest.raises(OutputError, match="two inputs"):
        collect_jobs([tree / "pkg_a" / "robot_a.urdf", other / "robot_a.urdf"], tmp_path / "o")


def test_output_over_input_is_refused(tree):
    with pytest.raises(OutputError, match="in-place"):
        collect_jobs([tree], tree)


@pytest.mark.parametrize("make", ["missing", "empty"])
def test_bad_inputs_are_refused(tmp_path, make):
    target = tmp_path / "nothing"
    if make == "empty":
        target.mkdir()
    with pytest.raises(UrdfError):
        collect_jobs([target], tmp_path / "out")


def test_results_are_identical_for_any_jobs_and_cache(tree, tmp_path):
    options = FixOptions(recompute="all")
    runs = {
        "serial, no cache": BatchSettings(jobs=1, use_cache=False),
        "2 workers, cold cache": BatchSettings(jobs=2, cache_dir=tmp_path / "c"),
        "2 workers, warm cache": BatchSettings(jobs=2, cache_dir=tmp_path / "c"),
        "serial, warm cache": BatchSettings(jobs=1, cache_dir=tmp_path / "c"),
    }
    found = {}
    for name, settings in runs.items():
        out = tmp_path / name.replace(" ", "_").replace(",", "")
        report = run_batch(collect_jobs([tree], out), options, settings)
        assert not report.failed, report.failed
        found[name] = outputs(out)
        if "warm" in name:  # every file's whole result is reused
            assert (report.file_hits, report.meshes) == (3, 0)
        else:
            assert (report.file_hits, report.meshes) == (0, 2)
    reference = found.pop("serial, no cache")
    assert len(reference) == 3
    assert b"<inertial>" in reference["pkg_a/robot_a.urdf"]
    for name, files in found.items():
        assert files == reference, name


@pytest.mark.parametrize("cache", [True, False])
def test_workers_start_only_for_enough_work(tree, tmp_path, monkeypatch, cache):
    """Two workers are asked for: a run whose meshes still to compute are under the
    threshold stays in this process, one over it starts them (with or without a cache),
    and the outputs are the same."""
    asked: list[int] = []

    @contextlib.contextmanager
    def recording(jobs, dask):
        asked.append(jobs)
        with threads(jobs, dask) as pool:
            yield pool if jobs > 1 else None

    monkeypatch.setattr(batch, "open_executor", recording)
    sizes = sum(p.stat().st_size for p in (tree / "pkg_a" / "meshes").glob("*.stl"))
    found = {}
    for name, limit in (("small", sizes + 1), ("large", sizes)):
        monkeypatch.setattr(batch, "WORKERS_FROM_BYTES", limit)
        settings = BatchSettings(jobs=2, use_cache=cache, cache_dir=tmp_path / f"c-{name}")
        report = run_batch(collect_jobs([tree], tmp_path / name), FixOptions(recompute="all"),
                           settings)
        assert not report.failed
        found[name] = outputs(tmp_path / name)
    assert asked == [1, 2]
    assert found["small"] == found["large"]


def test_batch_output_equals_the_single_file_command(tree, tmp_path):
    source = tree / "pkg_a" / "robot_a.urdf"
    # the outputs land in different folders: mesh references kept, so the bytes compare
    assert main(["fix", "--all", str(source), "-o", str(tmp_path / "single.urdf"), "-q",
                 "--cache-dir", str(tmp_path / "c"), "--keep-mesh-paths"]) == 0
    assert main(["fix", "--all", str(tree), "-o", str(tmp_path / "many"), "-q", "--jobs", "2",
                 "--cache-dir", str(tmp_path / "c"), "--keep-mesh-paths"]) == 0
    single = (tmp_path / "single.urdf").read_bytes()
    assert (tmp_path / "many" / "pkg_a" / "robot_a.urdf").read_bytes() == single


@contextlib.contextmanager
def threads(jobs, dask):
    with cf.ThreadPoolExecutor(2) as pool:
        yield pool


def test_each_distinct_mesh_is_read_once_with_workers(tree, tmp_path, monkeypatch):
    reads: list[str] = []
    real = meshlib.load_mesh  # the worker task (batch.tasks.mesh_task) reads through it too
    monkeypatch.setattr(meshlib, "load_mesh", lambda p, m: reads.append(p) or real(p, m))
    monkeypatch.setattr(batch, "open_executor", threads)  # same process: reads are seen
    report = run_batch(collect_jobs([tree], tmp_path / "out"), FixOptions(recompute="all"),
                       BatchSettings(jobs=2, use_cache=False))
    assert not report.failed
    assert sorted(Path(p).name for p in reads) == ["ball.stl", "box.stl"]


def test_each_distinct_mesh_is_read_once_in_one_process(tree, tmp_path, monkeypatch):
    reads: list[str] = []
    real = meshlib.load_mesh
    monkeypatch.setattr(meshlib, "load_mesh", lambda p, m: reads.append(p) or real(p, m))
    run_batch(collect_jobs([tree], tmp_path / "out"), FixOptions(recompute="all"),
              BatchSettings(jobs=1, use_cache=False))
    assert sorted(Path(p).name for p in reads) == ["ball.stl", "box.stl"]


@pytest.fixture
def broken(tree) -> Path:
    (tree / "pkg_b" / "bad_xml.urdf").write_text("<robot name='x'><link name='a'>")
    (tree / "pkg_b" / "no_mesh.urdf").write_text(robot(
        "m", link("l", '<mesh filename="missing.stl"/>')))
    return tree


@pytest.mark.parametrize("jobs", [1, 2])
def test_failures_are_reported_per_file_and_the_rest_is_written(broken, tmp_path, jobs):
    out = tmp_path / "out"
    report = run_batch(collect_jobs([broken], out), STRICT_ALL,
                       BatchSettings(jobs=jobs, use_cache=False))
    failed = {o.source.name: o.error for o in report.failed}
    assert set(failed) == {"bad_xml.urdf", "no_mesh.urdf"}
    assert "malformed XML" in failed["bad_xml.urdf"]
    assert "missing.stl" in failed["no_mesh.urdf"]
    assert sorted(outputs(out)) == ["pkg_a/robot_a.urdf", "pkg_a/sub/robot_b.urdf",
                                    "pkg_b/robot_c.urdf"]


def test_cli_exit_code_names_each_failed_file(broken, tmp_path, capsys):
    code = main(["fix", "--all", str(broken), "-o", str(tmp_path / "out"), "--jobs", "2", "-q",
                 "--no-cache", "--strict"])
    err = capsys.readouterr().err
    assert code == 2
    assert "bad_xml.urdf" in err and "no_mesh.urdf" in err
    assert "5 files: 3 written" in err and "2 failed" in err
    written = sorted(p.name for p in (tmp_path / "out").rglob("*.urdf"))
    assert len(written) == 3 and "bad_xml.urdf" not in written and "no_mesh.urdf" not in written


def test_cli_batch_exit_1_lists_the_links_left(broken, tmp_path, capsys):
    (broken / "pkg_b" / "bad_xml.urdf").unlink()
    code = main(["fix", "--all", str(broken), "-o", str(tmp_path / "out"), "-q", "--no-cache"])
    err = capsys.readouterr().err
    assert code == 1, err
    assert "left as it was" in err and "no_mesh.urdf" in err and "link 'l'" in err
    assert "4 files: 4 written (1 with links left as they were: 1 links), 0 failed" in err
    assert (tmp_path / "out" / "pkg_b" / "no_mesh.urdf").is_file()


def test_cli_several_inputs_need_an_output_folder(tree, capsys):
    before = {p: p.read_bytes() for p in tree.rglob("*") if p.is_file()}
    code = main(["fix", "--all", str(tree / "pkg_a" / "robot_a.urdf"), str(tree / "pkg_b")])
    assert code == 2
    captured = capsys.readouterr()
    (line,) = captured.err.splitlines()
    assert "-o FOLDER or --in-place" in line and captured.out == ""
    assert {p: p.read_bytes() for p in tree.rglob("*") if p.is_file()} == before


def test_cli_in_place_batch_keeps_backups(tree, tmp_path):
    before = (tree / "pkg_a" / "robot_a.urdf").read_bytes()
    assert main(["fix", "--all", str(tree), "--in-place", "-q", "--no-cache"]) == 0
    assert (tree / "pkg_a" / "robot_a.urdf.bak").read_bytes() == before
    assert (tree / "pkg_a" / "robot_a.urdf").read_bytes() != before


def test_cli_json_lists_every_file(tree, tmp_path):
    import json

    report = tmp_path / "r.json"
    assert main(["fix", "--all", str(tree), "-o", str(tmp_path / "out"), "-q", "--no-cache",
                 "--json", str(report)]) == 0
    doc = json.loads(report.read_text())
    assert sorted(Path(f["file"]).name for f in doc["files"]) == [
        "robot_a.urdf", "robot_b.urdf", "robot_c.urdf"]
    assert all(f["links"] for f in doc["files"])


def test_single_file_with_workers_matches_serial(tree, tmp_path):
    source = str(tree / "pkg_a" / "robot_a.urdf")
    assert main(["fix", "--all", source, "-o", str(tmp_path / "one.urdf"), "-q", "--no-cache"]) == 0
    assert main(["fix", "--all", source, "-o", str(tmp_path / "two.urdf"), "-q", "--no-cache",
                 "--jobs", "2"]) == 0
    assert (tmp_path / "one.urdf").read_bytes() == (tmp_path / "two.urdf").read_bytes()


def test_in_memory_jobs_keep_their_document(tree):
    report = run_batch([FileJob(tree / "pkg_b" / "robot_c.urdf")], FixOptions(recompute="all"),
                       BatchSettings(use_cache=False))
    assert report.outcomes[0].document is not None
    assert b"<inertial>" in report.outcomes[0].document


def test_warm_results_follow_edited_meshes_and_options(tree, tmp_path):
    cache = tmp_path / "c"

    def run(name, options=None, **kw):
        out = tmp_path / name
        report = run_batch(collect_jobs([tree], out), options or FixOptions(recompute="all"),
                           BatchSettings(cache_dir=cache, **kw))
        assert not report.failed
        return report, outputs(out)

    run("cold")
    trimesh.creation.box(extents=(0.4, 0.1, 0.05)).export(tree / "pkg_a" / "meshes" / "box.stl")
    report, edited = run("edited mesh")
    assert report.file_hits == 1  # robot_c has no mesh; a and b use box.stl
    _, fresh = run("reference", use_cache=False)
    assert edited == fresh
    report, heavier = run("other density",
                          FixOptions(recompute="all", mass="density", density=2000.0))
    assert report.file_hits == 0
    assert heavier != fresh


def test_a_corrupt_whole_file_entry_is_recomputed(tree, tmp_path):
    cache = tmp_path / "c"
    run_batch(collect_jobs([tree], tmp_path / "cold"), FixOptions(recompute="all"),
              BatchSettings(cache_dir=cache))
    entries = sorted((cache / "files-v1").glob("??/*.entry"))
    assert len(entries) == 3
    for entry in entries:
        data = entry.read_bytes()
        entry.write_bytes(data[:-10] + b"<evil/>   ")  # same length, other document
    report = run_batch(collect_jobs([tree], tmp_path / "warm"), FixOptions(recompute="all"),
                       BatchSettings(cache_dir=cache))
    assert report.file_hits == 0  # the document's digest no longer matches
    assert b"<evil/>" not in b"".join(outputs(tmp_path / "warm").values())
    for entry in entries:
        entry.write_bytes(b"garbage")
    report = run_batch(collect_jobs([tree], tmp_path / "again"), FixOptions(recompute="all"),
                       BatchSettings(cache_dir=cache))
    assert report.file_hits == 0
    assert outputs(tmp_path / "again") == outputs(tmp_path / "cold")


def test_whole_file_results_do_not_depend_on_the_working_folder(tree, tmp_path, monkeypatch):
    cache = tmp_path / "c"
    monkeypatch.chdir(tree)
    run_batch(collect_jobs([Path("pkg_a")], tmp_path / "one"), FixOptions(recompute="all"),
              BatchSettings(cache_dir=cache))
    monkeypatch.chdir(tmp_path)
    report = run_batch(collect_jobs([tree / "pkg_a"], tmp_path / "two"),
                       FixOptions(recompute="all"),
                       BatchSettings(cache_dir=cache))
    assert report.file_hits == 2
    assert outputs(tmp_path / "one") == outputs(tmp_path / "two")


def test_errors_fixed_by_the_inputs_are_cached_until_the_inputs_change(broken, tmp_path):
    cache = tmp_path / "c"

    def run(name):
        report = run_batch(collect_jobs([broken], tmp_path / name), STRICT_ALL,
                           BatchSettings(cache_dir=cache))
        return report, {o.source.name: o.error for o in report.failed}

    _, cold = run("cold")
    assert set(cold) == {"bad_xml.urdf", "no_mesh.urdf"}
    report, warm = run("warm")
    assert warm == cold  # the same one-line errors, from the cache
    assert report.file_hits == 5 and report.cache_hits == 0
    # the missing mesh appears: the entry no longer holds, the file is fixed
    trimesh.creation.box(extents=(0.1, 0.1, 0.1)).export(broken / "pkg_b" / "missing.stl")
    report, fixed = run("fixed")
    assert set(fixed) == {"bad_xml.urdf"}
    assert report.file_hits == 4
    assert (tmp_path / "fixed" / "pkg_b" / "no_mesh.urdf").is_file()


def test_a_cached_error_names_the_source_as_spelled(broken, tmp_path, monkeypatch):
    cache = tmp_path / "c"
    monkeypatch.chdir(broken)
    first = run_batch(collect_jobs([Path("pkg_b")], tmp_path / "one"), STRICT_ALL,
                      BatchSettings(cache_dir=cache))
    second = run_batch(collect_jobs([broken / "pkg_b"], tmp_path / "two"), STRICT_ALL,
                       BatchSettings(cache_dir=cache))
    errors = [sorted(o.error for o in r.failed) for r in (first, second)]
    assert all(e.startswith("pkg_b") for e in errors[0])
    assert all(e.startswith(str(broken)) for e in errors[1])
    assert second.file_hits == 1  # robot_c; the errors quote the other spelling


def test_errors_that_may_depend_on_the_environment_are_not_cached(tree, tmp_path,
                                                                   monkeypatch):
    from urdfinertia.errors import MeshError

    def unreadable(path, max_faces):
        raise MeshError(f"cannot read {path}: permission denied")

    monkeypatch.setattr(meshlib, "load_mesh", unreadable)
    cache = tmp_path / "c"
    for name in ("one", "two"):
        report = run_batch(collect_jobs([tree], tmp_path / name), STRICT_ALL,
                           BatchSettings(cache_dir=cache))
        assert {o.source.name for o in report.failed} == {"robot_a.urdf", "robot_b.urdf"}
        assert report.file_hits == (0 if name == "one" else 1)  # robot_c only


def test_a_mesh_failing_for_its_bytes_is_reused_though_its_message_names_it(tree,
                                                                              tmp_path):
    """An element dropped because its mesh holds no triangles (a fault of the file's
    bytes whose message names the mesh): the file's result is reused by the next run,
    until that mesh changes."""
    empty = tree / "pkg_a" / "meshes" / "empty.obj"
    empty.write_text("# no faces\nv 0 0 0\n")
    (tree / "pkg_a" / "robot_a.urdf").write_text(robot(
        "a", link("base", '<mesh filename="meshes/box.stl"/>')
        .replace("</link>", '<collision><geometry><mesh filename="meshes/empty.obj"/>'
                            "</geometry></collision></link>")))
    options = FixOptions(recompute="all")
    cache = tmp_path / "c"

    def run(name):
        return run_batch(collect_jobs([tree / "pkg_a" / "robot_a.urdf"], tmp_path / name),
                         options, BatchSettings(cache_dir=cache))

    first = run("one")
    (outcome,) = first.outcomes
    assert outcome.error is None and any("holds no triangles" in p for p in outcome.problems)
    assert first.file_hits == 0
    second = run("two")
    assert second.file_hits == 1
    assert second.outcomes[0].problems == outcome.problems
    assert (tmp_path / "two" / "robot_a.urdf").read_bytes() == \
        (tmp_path / "one" / "robot_a.urdf").read_bytes()
    trimesh.creation.box(extents=(0.1, 0.1, 0.1)).export(empty)  # the mesh is mended
    third = run("three")
    assert third.file_hits == 0 and not third.outcomes[0].problems


def test_a_warm_run_writes_every_output_and_keeps_the_order(tree, tmp_path):
    settings = BatchSettings(cache_dir=tmp_path / "c")
    run_batch(collect_jobs([tree], tmp_path / "cold"), STRICT_ALL, settings)
    jobs = collect_jobs([tree], tmp_path / "warm")
    report = run_batch(jobs, STRICT_ALL, settings)  # every file from the cache
    assert report.file_hits == 3
    assert [o.source for o in report.outcomes] == [j.source for j in jobs]
    assert all(o.output == j.output and o.document is None
               for o, j in zip(report.outcomes, jobs, strict=True))
    assert outputs(tmp_path / "warm") == outputs(tmp_path / "cold")
    assert report.times.get("write") > 0


def test_urdf_files_finds_what_rglob_finds(tmp_path):
    from urdfinertia.batch.inputs import description_files

    (tmp_path / "a" / "b").mkdir(parents=True)
    (tmp_path / "other").mkdir()
    for name in ("a/x.urdf", "a/b/y.URDF", "a/.urdf", "a/z.urdf.bak", "a/b/w.xml",
                 "other/v.urdf", ".hidden.urdf"):
        (tmp_path / name).write_text("<robot/>")
    (tmp_path / "dir.urdf").mkdir()
    (tmp_path / "a" / "link.urdf").symlink_to(tmp_path / "other" / "v.urdf")
    (tmp_path / "a" / "loop").symlink_to(tmp_path / "a")  # not followed
    expected = sorted(p for p in tmp_path.rglob("*")
                      if p.suffix.lower() == ".urdf" and p.is_file())
    assert sorted(description_files(tmp_path)) == expected
    assert len(expected) == 5


def test_an_altered_error_entry_is_recomputed(broken, tmp_path):
    cache = tmp_path / "c"
    source = broken / "pkg_b" / "no_mesh.urdf"
    run_batch([FileJob(source)], STRICT_ALL, BatchSettings(cache_dir=cache))
    (entry,) = (cache / "files-v1").glob("??/*.entry")
    data = entry.read_bytes()
    at = data.rindex(b"missing.stl")  # in the message (the body), not in the header
    entry.write_bytes(data[:at] + b"ELSEWHERE!!" + data[at + 11:])  # same length
    report = run_batch([FileJob(source)], STRICT_ALL, BatchSettings(cache_dir=cache))
    assert report.file_hits == 0
    assert "missing.stl" in report.outcomes[0].error


def test_links_left_for_the_environment_are_not_cached(tree, tmp_path, monkeypatch):
    """Without --strict an unreadable mesh leaves its link: that outcome is not cached
    either, so the next run reads the mesh again."""
    from urdfinertia.errors import MeshError

    real = meshlib.load_mesh

    def unreadable(path, max_faces):
        raise MeshError(f"cannot read {path}: permission denied")

    monkeypatch.setattr(meshlib, "load_mesh", unreadable)
    cache = tmp_path / "c"
    report = run_batch(collect_jobs([tree], tmp_path / "one"), FixOptions(recompute="all"),
                       BatchSettings(cache_dir=cache))
    assert not report.failed and sum(bool(o.left) for o in report.outcomes) == 2
    monkeypatch.setattr(meshlib, "load_mesh", real)
    report = run_batch(collect_jobs([tree], tmp_path / "two"), FixOptions(recompute="all"),
                       BatchSettings(cache_dir=cache))
    assert report.file_hits == 1 and not any(o.left for o in report.outcomes)


def test_folders_give_sdf_world_and_mjcf_but_not_other_xml(tmp_path):
    from urdfinertia.batch.inputs import collect_jobs

    files = {"r.urdf": "<robot/>", "m.sdf": "<sdf/>", "w.WORLD": "<sdf/>",
             "arm.xml": "<?xml version='1.0'?>\n<!-- x -->\n<mujoco model='a'/>",
             "package.xml": "<package/>", "launch.xml": "<launch/>",
             "macro.urdf.xacro": "<robot/>"}
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    jobs = collect_jobs([tmp_path], tmp_path / "out")
    assert sorted(j.source.name for j in jobs) == ["arm.xml", "m.sdf", "r.urdf", "w.WORLD"]
    assert {j.output.name for j in jobs} == {"arm.xml", "m.sdf", "r.urdf", "w.WORLD"}


@pytest.fixture
def checked_tree(tmp_path) -> Path:
    """Links with an inertial (so their geometry is checked: hull points of collision and
    visual meshes) and a visual-only mesh."""
    root = tmp_path / "checked"
    root.mkdir()
    trimesh.creation.box(extents=(0.2, 0.1, 0.05)).export(root / "box.stl")
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(root / "ball.stl")
    trimesh.creation.icosphere(subdivisions=1, radius=0.08).export(root / "shell.stl")
    inertial = ('<inertial><mass value="1"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" '
                'ixy="0" ixz="0" iyz="0"/></inertial>')
    body = ('<link name="{n}">' + inertial + '<visual><geometry><mesh filename="shell.stl"/>'
            '</geometry></visual><collision><geometry><mesh filename="{m}"/></geometry>'
            '</collision></link>\n')
    for name, mesh in (("one", "box.stl"), ("two", "ball.stl")):
        (root / f"{name}.urdf").write_text(robot(name, body.format(n="l", m=mesh)))
    return root


def test_workers_read_each_mesh_once_for_its_points_and_solids(checked_tree, tmp_path,
                                                                monkeypatch):
    reads: list[str] = []
    real = meshlib.load_mesh
    monkeypatch.setattr(meshlib, "load_mesh", lambda p, m: reads.append(p) or real(p, m))
    monkeypatch.setattr(batch, "open_executor", threads)
    report = run_batch(collect_jobs([checked_tree], tmp_path / "two"), FixOptions(),
                       BatchSettings(jobs=2, cache_dir=tmp_path / "c"))
    assert not report.failed
    assert sorted(Path(p).name for p in reads) == ["ball.stl", "box.stl", "shell.stl"]
    # the points went to the mesh cache too: a single-process run that computes every
    # file (details: no whole-file results) reads no mesh
    reads.clear()
    one = run_batch(collect_jobs([checked_tree], tmp_path / "one"), FixOptions(),
                    BatchSettings(jobs=1, cache_dir=tmp_path / "c", details=True))
    assert not one.failed and reads == []
    assert outputs(tmp_path / "one") == outputs(tmp_path / "two")


@pytest.mark.parametrize("cache", [True, False])
def test_workers_compute_each_hull_volume_once_and_the_gathering_process_none(
        checked_tree, tmp_path, monkeypatch, cache):
    import threading

    calls: list[bool] = []  # True: on the thread that gathers the results
    real = meshlib.unit_hull_volume

    def counted(points):
        calls.append(threading.current_thread() is threading.main_thread())
        return real(points)

    monkeypatch.setattr(meshlib, "unit_hull_volume", counted)
    monkeypatch.setattr(batch, "open_executor", threads)
    settings = (BatchSettings(jobs=2, cache_dir=tmp_path / "c") if cache
                else BatchSettings(jobs=2, use_cache=False))
    report = run_batch(collect_jobs([checked_tree], tmp_path / "two"),
                       FixOptions(recompute="all"), settings)
    assert not report.failed
    # one Qhull per mesh file (box, ball, shell), in the workers; the file tasks and the
    # gathering process reuse the volume the worker sent
    assert len(calls) == 3 and not any(calls)
    # and the result is the one a single process computes for itself
    one = run_batch(collect_jobs([checked_tree], tmp_path / "one"),
                    FixOptions(recompute="all"), BatchSettings(jobs=1, use_cache=False))
    assert not one.failed
    assert outputs(tmp_path / "one") == outputs(tmp_path / "two")


def test_mesh_needs_lists_every_mesh_of_a_checked_link_for_points(checked_tree):
    solids, points = batch.mesh_needs(checked_tree / "one.urdf", FixOptions())
    assert [p.name for p in solids] == ["box.stl"]
    assert sorted(p.name for p in points) == ["box.stl", "shell.stl"]


def test_a_warm_fix_imports_no_numerical_or_xacro_library(tree, tmp_path):
    """A warm ``fix DIR -o OUT`` (every file from the cache, mesh references relocated to
    the output folder) runs in a fresh interpreter without numpy, lxml or xacro support;
    the cold run before it needs them all, which shows the check can fail."""
    import subprocess
    import sys

    heavy = ("numpy", "lxml", "scipy", "trimesh", "xacro", "xml.dom",
             "urdfinertia.descriptions.xacro.expand")
    code = ("import sys\n"
            "from urdfinertia.cli import main\n"
            "code = main(sys.argv[1:])\n"
            f"heavy = {heavy!r}\n"
            "print(sorted(m for m in sys.modules if m in heavy))\n"
            "sys.exit(code)\n")
    env = {**os.environ, "URDFINERTIA_CACHE_DIR": str(tmp_path / "cache")}

    def run(out: str) -> list[str]:
        proc = subprocess.run([sys.executable, "-c", code, "fix", str(tree), "-o",
                               str(tmp_path / out), "--all", "-q"],
                              capture_output=True, text=True, env=env, check=False)
        assert proc.returncode == 0, proc.stderr
        return ast.literal_eval(proc.stdout.strip().splitlines()[-1])

    assert {"numpy", "lxml"} <= set(run("cold"))
    assert run("warm") == []
    assert outputs(tmp_path / "warm") == outputs(tmp_path / "cold")


@pytest.mark.parametrize("cache", [True, False])
def test_outputs_holding_the_bytes_are_left_untouched(tree, tmp_path, cache):
    settings = BatchSettings(cache_dir=tmp_path / "c", use_cache=cache)
    out = tmp_path / "out"
    first = run_batch(collect_jobs([tree], out), STRICT_ALL, settings)
    assert first.untouched == 0 and first.up_to_date == (False,) * 3
    before = {p: p.stat() for p in out.rglob("*.urdf")}
    for p in before:
        os.utime(p, ns=(1_000_000_000, 1_000_000_000))
    stale = out / "pkg_b" / "robot_c.urdf"
    stale.write_bytes(stale.read_bytes() + b"\n")  # an output edited since: rewritten
    before = {p: p.stat() for p in out.rglob("*.urdf")}
    second = run_batch(collect_jobs([tree], out), STRICT_ALL, settings)
    assert second.file_hits == (3 if cache else 0)
    assert [o.source.name for o in second.outcomes] == [
        "robot_a.urdf", "robot_b.urdf", "robot_c.urdf"]
    assert second.up_to_date == (True, True, False) and second.untouched == 2
    after = {p: p.stat() for p in out.rglob("*.urdf")}
    for p, st in before.items():
        kept = (after[p].st_ino, after[p].st_mtime_ns) == (st.st_ino, st.st_mtime_ns)
        assert kept == (p != stale), p
    assert outputs(out) == outputs(_fresh(tree, tmp_path))


def _fresh(tree: Path, tmp_path: Path) -> Path:
    out = tmp_path / "fresh"
    run_batch(collect_jobs([tree], out), STRICT_ALL, BatchSettings(use_cache=False))
    return out


def test_cli_says_which_outputs_were_left_untouched(tree, tmp_path, capsys, monkeypatch):
    import json

    monkeypatch.setenv("COLUMNS", "400")  # the table's cells unfolded
    argv = ["fix", "--all", str(tree), "-o", str(tmp_path / "out"), "--cache-dir",
            str(tmp_path / "c"), "--json", str(tmp_path / "r.json")]
    assert main(argv) == 0
    assert "already held these bytes" not in capsys.readouterr().err
    assert not any(f["output_up_to_date"]
                   for f in json.loads((tmp_path / "r.json").read_text())["files"])
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "3 of them already held these bytes and were left untouched" in err
    assert err.count("up to date, untouched") == 3
    assert all(f["output_up_to_date"]
               for f in json.loads((tmp_path / "r.json").read_text())["files"])


@pytest.mark.parametrize(("deps", "ok"), [
    ([["uri", "folder", "path", "key"]] * 3, True),
    ([], True),
    ([["uri", "folder", "path", 1]], False),
    ([["uri", "folder", "path"]], False),
    ([["uri", "folder", "path", "key"], "uri"], False),
    ({"uri": "folder"}, False),
    (None, False),
])
def test_a_whole_file_entry_needs_its_meshes_as_rows_of_four_strings(deps, ok):
    from urdfinertia.batch import file_cache

    result = file_cache.CachedResult("r", 1, 1, (), b"<robot/>")
    data = file_cache.encode("k", deps, result)
    assert (file_cache.decode(data, "k") is not None) == ok
