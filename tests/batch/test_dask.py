"""--dask: the same per-file work on a Dask LocalCluster gives the local run's bytes."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh

from urdfinertia.batch.executors import ClusterError, connect_dask
from urdfinertia.batch.inputs import collect_jobs
from urdfinertia.batch.run import BatchSettings, run_batch
from urdfinertia.body.options import FixOptions
from urdfinertia.cli import main

distributed = pytest.importorskip("distributed")

URDF = """<?xml version="1.0"?>
<robot name="{name}">
  <link name="body"><collision><geometry><mesh filename="{mesh}" scale="{scale}"/>
  </geometry></collision></link>
  <link name="arm"><collision><geometry><cylinder radius="0.02" length="0.3"/>
  </geometry></collision></link>
</robot>
"""


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as c:
        yield c


@pytest.fixture
def tree(tmp_path) -> Path:
    root = tmp_path / "robots"
    (root / "meshes").mkdir(parents=True)
    trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(root / "meshes" / "box.stl")
    trimesh.creation.capsule(height=0.2, radius=0.05).export(root / "meshes" / "pill.obj")
    (root / "one.urdf").write_text(URDF.format(name="one", mesh="meshes/box.stl",
                                               scale="1 1 1"))
    (root / "two").mkdir()
    (root / "two" / "two.urdf").write_text(URDF.format(name="two", mesh="../meshes/pill.obj",
                                                       scale="1 -2 1"))
    (root / "two" / "bad.urdf").write_text(URDF.format(name="bad", mesh="nope.stl",
                                                       scale="1 1 1"))
    return root


def outputs(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*.urdf"))}


def test_dask_run_equals_local_run(cluster, tree, tmp_path):
    options = FixOptions(strict=True, recompute="all")  # bad.urdf (missing mesh) fails
    local = run_batch(collect_jobs([tree], tmp_path / "local"), options,
                      BatchSettings(use_cache=False))
    remote = run_batch(collect_jobs([tree], tmp_path / "dask"), options,
                       BatchSettings(dask=cluster.scheduler_address,
                                     cache_dir=tmp_path / "cache"))
    assert outputs(tmp_path / "dask") == outputs(tmp_path / "local")
    assert len(outputs(tmp_path / "local")) == 2
    assert [o.error for o in remote.outcomes] == [o.error for o in local.outcomes]
    assert [o.source.name for o in remote.failed] == ["bad.urdf"]
    assert remote.meshes == 2


def test_dask_from_the_command_line(cluster, tree, tmp_path, capsys):
    code = main(["fix", "--all", str(tree / "one.urdf"), str(tree / "two" / "two.urdf"),
                 "-o", str(tmp_path / "out"), "--dask", cluster.scheduler_address, "-q",
                 "--no-cache"])
    assert code == 0, capsys.readouterr().err
    assert sorted(outputs(tmp_path / "out")) == ["one.urdf", "two.urdf"]


def test_unreachable_scheduler_is_a_one_line_error():
    with pytest.raises(ClusterError, match="cannot connect"):
        connect_dask("tcp://127.0.0.1:9", timeout="1s")
