"""Every MJCF model of the installed collections that uses ``<compiler meshdir/texturedir/
assetdir>`` or ``<include>`` compiles in MuJoCo from another folder once relocated.

The collections are read as files (dm_control, robosuite, gymnasium_robotics and
metaworld ship their models inside the package; none is imported, so their own
dependencies need not be installed: ``pip install --no-deps NAME`` is enough). A model
MuJoCo does not compile where it lies (a fragment meant to be included, a feature of
another MuJoCo version) is skipped: only what worked must keep working.
"""

from __future__ import annotations

import pytest
from support.corpus import mjcf_models_with_paths

from urdfinertia.descriptions.formats import relocate_references

mujoco = pytest.importorskip("mujoco")

MODELS = mjcf_models_with_paths()


@pytest.mark.skipif(not MODELS, reason="no MJCF collection installed (pip install --no-deps "
                                       "dm_control)")
@pytest.mark.parametrize("path", [p for _, p in MODELS], ids=[i for i, _ in MODELS])
def test_relocated_model_compiles_from_another_folder(path, tmp_path):
    try:
        mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        pytest.skip(f"does not compile where it lies: {str(exc).splitlines()[0]}")
    out = tmp_path / "a" / "b" / path.name
    out.parent.mkdir(parents=True)
    data = path.read_bytes()
    moved, _ = relocate_references(data, path, out)
    out.write_bytes(moved)
    mujoco.MjModel.from_xml_path(str(out))
