"""The pre-commit hook, installed and run by ``pre-commit try-repo`` in a new repository.

pre-commit installs this repository into a fresh virtualenv with pip. Offline (the test
machine reaches no index quickly), pip gets the build backend from virtualenv's bundled
setuptools wheel and finds the runtime dependencies already installed on PYTHONPATH: a
view of this interpreter's site-packages without urdfinertia itself, so the hook runs the
copy pre-commit built from the repository.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data" / "engines"
_OWN = ("urdfinertia", "__editable__", "pip", "setuptools", "pkg_resources",
        "_distutils_hack", "wheel")

pytestmark = pytest.mark.slow


def dependency_view(folder: Path) -> Path:
    folder.mkdir()
    for entry in Path(sysconfig.get_paths()["purelib"]).iterdir():
        if entry.suffix == ".pth" or entry.name.split("-")[0].split(".")[0] in _OWN:
            continue
        (folder / entry.name).symlink_to(entry)
    return folder


def test_hook_checks_descriptions_and_skips_other_xml(tmp_path):
    """One installed hook, every kind of file: URDFs, a package.xml (skipped), a USD
    layer, and xacro includes, which are checked through the robot including them."""
    pre_commit = shutil.which("pre-commit", path=str(Path(sys.executable).parent))
    if pre_commit is None or shutil.which("git") is None:
        pytest.skip("pre-commit or git not installed")
    import virtualenv

    repo = tmp_path / "repo"
    (repo / "urdf").mkdir(parents=True)
    shutil.copy(DATA / "tri.urdf", repo / "urdf" / "tri.urdf")
    shutil.copy(DATA / "fine.urdf", repo / "urdf" / "fine.urdf")
    (repo / "package.xml").write_text("<package><name>x</name></package>")
    shutil.copytree(ROOT / "tests" / "data" / "xacro" / "nested", repo / "nested")
    (repo / "usd").mkdir()
    shutil.copy(ROOT / "tests" / "data" / "usd" / "handmade" / "instanced.usda",
                repo / "usd" / "instanced.usda")
    (repo / "notes.txt").write_text("<robot/>")
    git = ["git", "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run([*git, "init", "-q"], cwd=repo, check=True)
    subprocess.run([*git, "add", "."], cwd=repo, check=True)
    env = dict(os.environ)
    env.update(
        PRE_COMMIT_HOME=str(tmp_path / "home"),
        PIP_NO_INDEX="1",
        PIP_FIND_LINKS=str(Path(virtualenv.__file__).parent / "seed" / "wheels" / "embed"),
        PYTHONPATH=str(dependency_view(tmp_path / "site")),
    )
    proc = subprocess.run([pre_commit, "try-repo", str(ROOT), "urdf-inertia-check",
                           "--all-files"], cwd=repo, env=env, capture_output=True,
                          text=True, timeout=600)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 1, out
    assert "urdf/tri.urdf: 3 links, 1 error(s)" in out
    assert "urdf/fine.urdf: 3 links, 0 error(s)" in out
    assert "package.xml" not in out.split("hook id")[-1]
    assert "notes.txt" not in out
    assert "usd/instanced.usda: 2 links, 0 error(s)" in out
    # the includes are not checked alone (0 links): the robot including them is, once
    for include in ("nested/parts/body.xacro", "nested/parts/sensors/head.xacro"):
        assert f"{include}: no links of its own: checked through " \
               "nested/rover.urdf.xacro" in out
    assert out.count("nested/rover.urdf.xacro: 3 links, ") == 1
    assert " 0 links" not in out
