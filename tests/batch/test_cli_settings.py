"""cli/batch.py: the speed options' defaults (workers, per-mesh time budget)."""

from __future__ import annotations

import argparse
import os

import pytest

from urdfinertia.cli.batch import add_batch_arguments, available_cores, settings_from_args
from urdfinertia.mesh.limits import BUDGET_ENV_VAR, mesh_seconds


def parse(*argv: str) -> argparse.Namespace:
    p = argparse.ArgumentParser()
    add_batch_arguments(p)
    return p.parse_args(list(argv))


def test_jobs_default_to_the_usable_cores():
    expected = (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                else os.cpu_count())
    assert available_cores() == expected
    assert settings_from_args(parse()).jobs == expected
    assert settings_from_args(parse("-j", "1")).jobs == 1


def test_mesh_seconds_reaches_the_repair_through_the_environment(monkeypatch):
    monkeypatch.setenv(BUDGET_ENV_VAR, "")  # restored (removed) after the test
    settings_from_args(parse("--mesh-seconds", "0.5"))
    assert os.environ[BUDGET_ENV_VAR] == "0.5"  # inherited by worker processes
    assert mesh_seconds() == pytest.approx(0.5)
    settings_from_args(parse("--mesh-seconds", "0"))
    assert mesh_seconds() is None  # 0: no limit


def test_check_and_report_compute_meshes_with_workers_and_say_the_same(tmp_path):
    """check and report take -j like fix: with workers they print and write what one
    process does (each with its own empty cache, so the workers really compute)."""
    import trimesh

    from urdfinertia.cli import main

    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(tmp_path / "ball.stl")
    trimesh.creation.box(extents=(0.2, 0.1, 0.05)).export(tmp_path / "box.stl")
    inertial = ('<inertial><mass value="{m}"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" '
                'ixy="0" ixz="0" iyz="0"/></inertial>')
    links = "".join(
        f'<link name="{n}">{inertial.format(m=m)}<collision><geometry><mesh filename="{f}"/>'
        f"</geometry></collision></link>"
        for n, m, f in (("a", 1.0, "ball.stl"), ("b", 900.0, "box.stl")))
    urdf = tmp_path / "r.urdf"
    urdf.write_text(f'<robot name="r">{links}<joint name="j" type="revolute"><parent '
                    f'link="a"/><child link="b"/><axis xyz="0 0 1"/><limit effort="1" '
                    f'velocity="1" lower="-1" upper="1"/></joint></robot>')
    out = {}
    for jobs in ("1", "2"):
        cache = str(tmp_path / f"cache-{jobs}")
        json_path = tmp_path / f"check-{jobs}.json"
        main(["check", str(urdf), "-q", "--json", str(json_path), "-j", jobs,
              "--cache-dir", cache])
        html = tmp_path / f"report-{jobs}.html"
        assert main(["report", str(urdf), "-o", str(html), "-j", jobs,
                     "--cache-dir", cache]) == 0
        assert any((tmp_path / f"cache-{jobs}").rglob("*.points.entry"))
        out[jobs] = (json_path.read_bytes(), html.read_bytes())
    assert out["1"] == out["2"]
