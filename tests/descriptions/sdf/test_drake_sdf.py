"""SDFormat against Drake: Drake reads our products of inertia as we mean them, and our fix
of a closed mesh model agrees with Drake's ``fix_inertia`` (which needs closed meshes).

Drake is in the dev extra (``pip install drake``). Skipped where no Python with ``pydrake`` is
found, except in the test command, which requires it (:mod:`support.drake_ref`).
"""

from __future__ import annotations

import numpy as np
import pytest
from support.drake_ref import drake_bodies, drake_fix_inertia, drake_python, drake_required
from support.sdf import sdf_doc

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.sdf.read import robot_from_bytes
from urdfinertia.plan.fix import fix_file

pytestmark = pytest.mark.skipif(drake_python() is None and not drake_required(),
                                reason="pydrake not available (pip install drake)")


def test_drake_reads_the_tensor_we_read(tmp_path):
    """Rotated inertial frame with non-zero products: same tensor in the link frame."""
    path = tmp_path / "t.sdf"
    path.write_bytes(sdf_doc("""<model name="m"><link name="a"><inertial>
      <pose>0.1 0.2 0.3 0.3 -0.2 0.5</pose><mass>2</mass>
      <inertia><ixx>0.3</ixx><ixy>0.05</ixy><ixz>-0.02</ixz><iyy>0.4</iyy><iyz>0.01</iyz>
      <izz>0.5</izz></inertia></inertial></link></model>""", "1.9"))
    body = drake_bodies(path)["bodies"]["m::a"]
    inertial = robot_from_bytes(path.read_bytes(), path).link("a").inertial
    np.testing.assert_allclose(body["com"], inertial.origin.xyz, atol=1e-15)
    np.testing.assert_allclose(body["inertia"], inertial.tensor_in_link(), atol=1e-14)


def test_closed_mesh_model_matches_drake_fix_inertia(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    mesh = trimesh.creation.annulus(r_min=0.05, r_max=0.1, height=0.04, sections=64)
    assert mesh.is_watertight
    mesh.export(tmp_path / "ring.obj")
    src = tmp_path / "ring.sdf"
    src.write_bytes(sdf_doc("""<model name="m">
  <link name="base">
    <inertial><mass>3</mass></inertial>
    <collision name="ring">
      <pose>0.02 -0.01 0.05 0.4 0.1 -0.3</pose>
      <geometry><mesh><uri>ring.obj</uri><scale>1 1.5 2</scale></mesh></geometry>
    </collision>
    <collision name="box">
      <pose>0 0 -0.1 0 0 0</pose>
      <geometry><box><size>0.1 0.2 0.05</size></box></geometry>
    </collision>
  </link>
</model>""", "1.9"))
    ours = tmp_path / "ours.sdf"
    ours.write_bytes(fix_file(src, FixOptions(recompute="all")).output)
    theirs = tmp_path / "drake.sdf"
    assert drake_fix_inertia(src, theirs) is None
    a = drake_bodies(ours)["bodies"]["m::base"]
    b = drake_bodies(theirs)["bodies"]["m::base"]
    assert a["mass"] == b["mass"] == 3.0
    # fix_inertia writes 5 significant digits ("%.5g"): that, not the maths, is the tolerance
    np.testing.assert_allclose(a["com"], b["com"], rtol=1e-4, atol=1e-9)
    np.testing.assert_allclose(a["inertia"], b["inertia"], rtol=1e-4,
                               atol=1e-4 * np.abs(b["inertia"]).max())
