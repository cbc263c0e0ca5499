"""usd/read.py and geometry.py on a hand-made asset: centimetre units, an instanced leg
(inherits + instanceable), a capsule along X, a cone along Y, a scaled cube."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from descriptions.usd.assets import DATA

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.model import Box, Capsule, Cone
from urdfinertia.descriptions.usd.read import read
from urdfinertia.descriptions.usd.write import override_path
from urdfinertia.plan.fix import fix_file

ASSET = DATA / "handmade" / "instanced.usda"


def test_units_axes_and_instanced_bodies():
    robot, _ = read_description(ASSET)
    base, shin = robot.link("base"), robot.link("shin")  # shin: inside an instance
    capsule, cone = (c.shape for c in base.collisions)
    assert capsule == Capsule(radius=0.05, length=0.2)  # cm -> m
    assert cone == Cone(radius=0.03, length=0.06)
    # the capsule's z is the prim's X axis, the cone's z (towards its apex) the prim's +Y
    np.testing.assert_allclose(base.collisions[0].origin.matrix()[:3, 2], [1, 0, 0],
                               atol=1e-12)
    np.testing.assert_allclose(base.collisions[1].origin.matrix()[:3, 2], [0, 1, 0],
                               atol=1e-12)
    np.testing.assert_allclose(base.collisions[1].origin.xyz, [0, 0.2, 0], atol=1e-12)
    assert base.inertial is None  # no MassAPI: the engine computes it
    assert shin.collisions[0].shape == Box(size=(0.1, 0.2, 0.4))  # size 10 cm x scale
    assert shin.inertial.mass == 2.0
    assert shin.inertial.ixx == pytest.approx(1e-4)  # 1 kg cm^2


def test_fix_overrides_a_body_inside_an_instance(tmp_path):
    shutil.copy(ASSET, tmp_path / "robot.usda")
    root = tmp_path / "robot.usda"
    fixed = fix_file(root, FixOptions(recompute="all"))
    layer = override_path(root)
    layer.write_bytes(fixed.output)
    assert "instanceable = false" in layer.read_text()
    composed = read(layer).robot
    want = {r.name: r.assembly.total for r in fixed.links if r.assembly is not None}
    assert set(want) == {"base", "shin"}
    for name, total in want.items():
        got = composed.link(name).inertial
        assert got is not None, name
        assert got.mass == pytest.approx(total.mass, rel=1e-6)
        np.testing.assert_allclose(got.tensor_in_link(), total.inertia,
                                   atol=1e-6 * np.abs(total.inertia).max())
    # the cone's CoM a quarter of its height above its base, towards +Y
    assert composed.link("base").inertial.origin.xyz[1] > 0
