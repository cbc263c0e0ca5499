"""A newcomer's notebook (tests/data/newcomer.ipynb) fixes a real robot, in a fresh
virtual environment with the package installed from the checkout (no dev extra), using only
what the API reference shows. Its code cells run in order as one script (no Jupyter kernel
is needed); each states its facts with ``assert``."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "tests" / "data" / "newcomer.ipynb"


def notebook_script(path: Path) -> str:
    """The notebook's code cells, in order, as one script."""
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    return "\n\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")


def test_the_notebook_uses_the_public_api_only():
    script = notebook_script(NOTEBOOK)
    imports = [ln.strip() for ln in script.splitlines() if ln.strip().startswith(("import",
                                                                               "from"))]
    assert imports and all(
        ln.startswith(("import os", "import urdfinertia", "from urdfinertia.rules",
                       "from pathlib")) for ln in imports), imports


@pytest.mark.slow
def test_the_newcomer_notebook_in_a_fresh_environment(tmp_path, erd_dir):
    robot = erd_dir / "robots" / "allegro_hand_description" / "urdf" / "allegro_right_hand.urdf"
    # the package from a copy of the checkout, so that building it leaves no files here
    source = tmp_path / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, source / name)
    shutil.copytree(ROOT / "src", source / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    env_dir = tmp_path / "venv"
    start = time.perf_counter()
    venv.EnvBuilder(with_pip=True).create(env_dir)
    python = env_dir / "bin" / "python"
    # --no-compile: byte-compiling every installed module (plotly alone has thousands) is
    # most of an install's time and not what is tested here
    installed = subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-compile",
                                "--disable-pip-version-check", str(source)],
                               capture_output=True, text=True, timeout=600)
    assert installed.returncode == 0, installed.stdout[-3000:] + installed.stderr[-3000:]
    setup = time.perf_counter() - start
    work = tmp_path / "work"
    work.mkdir()
    script = work / "newcomer.py"
    script.write_text(notebook_script(NOTEBOOK), encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env.update(ROBOT=str(robot), URDFINERTIA_CACHE_DIR=str(tmp_path / "cache"))
    start = time.perf_counter()
    ran = subprocess.run([str(python), str(script)], cwd=work, env=env, capture_output=True,
                         text=True, timeout=300)
    seconds = time.perf_counter() - start
    print(f"fresh environment: {setup:.1f} s to create and install, notebook {seconds:.1f} s")
    assert ran.returncode == 0, ran.stdout[-3000:] + ran.stderr[-3000:]
    assert "recomputed: triangle-inequality" in ran.stdout
    assert (work / "allegro.fixed.urdf").is_file()
    # the environment is the package's own: no dev tools, not this interpreter's packages
    listed = subprocess.run([str(python), "-m", "pip", "list", "--format", "json"],
                            capture_output=True, text=True, check=True)
    names = {p["name"].lower() for p in json.loads(listed.stdout)}
    assert "urdfinertia" in names and "pytest" not in names
    assert sys.prefix != str(env_dir)
