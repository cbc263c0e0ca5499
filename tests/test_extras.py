"""The lean core: ``check`` and ``fix`` without the ``report`` and ``fast`` extras.

A child interpreter runs without site-packages (``-S``) on a view of this environment's:
every distribution but the extras' (plotly, matplotlib, fast-simplification, libigl) and
urdfinertia's own install, with ``src`` first on the path. So the extras' modules are really
absent there, as after ``pip install urdfinertia``: the report says in one line which extra
to install, and check and fix give the same bytes as here, where the extras are installed
(libigl's winding numbers on one side, the numpy fallback on the other).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

from urdfinertia.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: Top-level names of what the extras install (modules, their data and dist-info).
EXTRAS = ("plotly", "_plotly_utils", "matplotlib", "mpl_toolkits", "pylab",
          "fast_simplification", "igl", "libigl")
_OWN = ("urdfinertia", "__editable__")
REPORT_LINE = ("urdf-inertia: error: the report needs the report extra: "
               "pip install 'urdfinertia[report]'")


@pytest.fixture(scope="module")
def core_path(tmp_path_factory) -> str:
    """PYTHONPATH of the core install: ``src`` and a view without the extras."""
    view = tmp_path_factory.mktemp("core-site")
    for entry in Path(sysconfig.get_paths()["purelib"]).iterdir():
        top = entry.name.split("-")[0].split(".")[0]
        if entry.suffix == ".pth" or top in EXTRAS or top.startswith(_OWN):
            continue
        (view / entry.name).symlink_to(entry)
    return os.pathsep.join([str(ROOT / "src"), str(view)])


def run_core(core_path: str, tmp_path: Path, code: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=core_path, URDFINERTIA_CACHE_DIR=str(tmp_path / "c"))
    return subprocess.run([sys.executable, "-S", "-c", code], env=env, capture_output=True,
                          text=True, timeout=300, cwd=tmp_path)


def cli(core_path: str, tmp_path: Path, *argv: str) -> subprocess.CompletedProcess:
    return run_core(core_path, tmp_path, "import sys; from urdfinertia.cli import main; "
                    f"sys.exit(main({list(argv)!r}))")


def test_the_view_lacks_the_extras(core_path, tmp_path):
    probe = run_core(core_path, tmp_path, "import importlib.util, json, urdfinertia; print("
                     "json.dumps({m: importlib.util.find_spec(m) is not None for m in "
                     "['plotly', 'matplotlib', 'fast_simplification', 'igl', 'numpy', "
                     "'trimesh', 'manifold3d']})); print(urdfinertia.__file__)")
    assert probe.returncode == 0, probe.stderr
    found, where = probe.stdout.splitlines()
    assert json.loads(found) == {"plotly": False, "matplotlib": False,
                                 "fast_simplification": False, "igl": False, "numpy": True,
                                 "trimesh": True, "manifold3d": True}
    assert Path(where.strip()).is_relative_to(ROOT / "src")


def test_report_without_the_extra_is_one_line(core_path, tmp_path, robots_dir):
    out = tmp_path / "r.html"
    done = cli(core_path, tmp_path, "report", str(robots_dir / "nm7mar.urdf"), "-o", str(out))
    assert done.returncode == 2
    assert done.stderr == REPORT_LINE + "\n"
    assert not out.exists()


def test_plot_without_the_extra_is_one_line(core_path, tmp_path, robots_dir):
    done = cli(core_path, tmp_path, "compare", str(robots_dir / "nm7mar.urdf"),
               "--plot", str(tmp_path / "p.png"))
    assert done.returncode == 2
    assert done.stderr.splitlines()[-1] == ("urdf-inertia: error: compare --plot needs the "
                                            "report extra: pip install 'urdfinertia[report]'")
    assert "Traceback" not in done.stderr


def test_python_report_without_the_extra_names_it(core_path, tmp_path, robots_dir):
    done = run_core(core_path, tmp_path, (
        "import urdfinertia\n"
        "from urdfinertia.errors import MissingExtraError, UrdfInertiaError\n"
        "try:\n"
        f"    urdfinertia.report({str(robots_dir / 'nm7mar.urdf')!r})\n"
        "except ImportError as exc:\n"
        "    assert isinstance(exc, MissingExtraError) and isinstance(exc, UrdfInertiaError)\n"
        "    print(exc.extra, exc.name, exc)\n"))
    assert done.returncode == 0, done.stderr
    assert done.stdout == ("report plotly the report needs the report extra: "
                           "pip install 'urdfinertia[report]'\n")


def test_check_and_fix_run_on_the_core(core_path, tmp_path, robots_dir):
    urdf = robots_dir / "nm7mar.urdf"
    core_out, here_out = tmp_path / "core.urdf", tmp_path / "here.urdf"
    checked = cli(core_path, tmp_path, "check", str(urdf), "-q")
    assert checked.returncode == 0, checked.stderr
    assert "4 links, 0 error(s), 6 warning(s)" in checked.stdout
    fixed = cli(core_path, tmp_path, "fix", str(urdf), "--spec",
                str(robots_dir / "nm7mar.inertia.toml"), "-o", str(core_out))
    assert fixed.returncode == 0, fixed.stderr
    assert main(["fix", str(urdf), "--spec", str(robots_dir / "nm7mar.inertia.toml"),
                 "-o", str(here_out)]) == 0
    assert core_out.read_bytes() == here_out.read_bytes()


def test_numpy_winding_numbers_give_the_same_fix(core_path, tmp_path, erd_dir):
    """Panda's visual link0 mesh is repaired with generalized winding numbers (its holes
    capped and voted on): the numpy sums of the core give the bytes libigl's give here."""
    mesh = erd_dir / "robots" / "panda_description" / "meshes" / "visual" / "link0.dae"
    urdf = tmp_path / "link0.urdf"
    urdf.write_text(f"""<robot name="p"><link name="link0"><inertial><mass value="2.9"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
      <visual><geometry><mesh filename="{mesh.as_uri()}"/></geometry></visual>
    </link></robot>""")
    argv = ["fix", str(urdf), "--no-cache", "-j", "1"]
    core_out, here_out = tmp_path / "core.urdf", tmp_path / "here.urdf"
    done = cli(core_path, tmp_path, *argv, "-o", str(core_out))
    assert done.returncode == 0, done.stderr
    assert main([*argv, "-o", str(here_out)]) == 0
    assert core_out.read_bytes() == here_out.read_bytes()
    assert b'ixx="1"' not in core_out.read_bytes()  # the placeholder was recomputed
