"""usd/read.py: converted robots read into the model; their MassAPI as the source said."""

from __future__ import annotations

import numpy as np
import pytest
from descriptions.usd.assets import all_assets, asset, source

from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.model import Box, Capsule, Cylinder, Sphere
from urdfinertia.descriptions.usd.read import valid_identifier

URDF_SOURCES = ["double_pendulum", "simple_humanoid", "cartpole", "spirit40"]
# float32 in USD: 6e-8 relative per value; a tensor through eigenvectors and a float32
# quaternion keeps about 1e-6 of its largest component
F32 = 1e-6


@pytest.mark.parametrize("name", all_assets())
def test_every_converted_robot_reads(name):
    robot, _ = read_description(asset(name))
    src, _ = read_description(source(name))
    assert robot.format == "usd"
    assert len(robot.links) >= 3
    # every body is a link of the source (a URDF's massless 'world' root is no body), and
    # every collision and visual element came through the payload layers
    assert {link.name for link in robot.links} <= {valid_identifier(lk.name)
                                                  for lk in src.links}
    assert len(robot.links) >= len(src.links) - 1
    for role in ("collisions", "visuals"):
        assert sum(len(getattr(lk, role)) for lk in robot.links) == \
            sum(len(getattr(lk, role)) for lk in src.links)
    # the converters write newton:inertia beside the MassAPI: our principalAxes
    # convention (T = R diag R^T) is theirs, so no disagreement is found
    assert not [f for f in robot.findings if f.code == "usd-newton-mass-disagrees"]


@pytest.mark.parametrize("name", URDF_SOURCES)
def test_mass_api_equals_the_source_urdf(name):
    usd, _ = read_description(asset(name))
    urdf, _ = read_description(source(name))
    compared = 0
    for link in urdf.links:
        if link.inertial is None or link.inertial.mass <= 0:
            continue
        got = usd.link(valid_identifier(link.name)).inertial
        assert got is not None, link.name
        assert got.mass == pytest.approx(link.inertial.mass, rel=F32)
        np.testing.assert_allclose(got.origin.xyz, link.inertial.origin.xyz, atol=F32)
        want = link.inertial.tensor_in_link()
        np.testing.assert_allclose(got.tensor_in_link(), want,
                                   atol=F32 * max(np.abs(want).max(), 1e-12))
        compared += 1
    assert compared >= 2


def test_primitives_and_their_frames_match_the_source():
    usd, _ = read_description(asset("spirit40"))
    urdf, _ = read_description(source("spirit40"))
    seen = set()
    for link in urdf.links:
        mine = usd.link(valid_identifier(link.name)).collisions
        assert len(mine) == len(link.collisions)
        for a, b in zip(link.collisions, mine, strict=True):
            assert type(a.shape) is type(b.shape)
            seen.add(type(a.shape))
            pa, pb = a.origin.matrix(), b.origin.matrix()
            np.testing.assert_allclose(pb[:3, 3], pa[:3, 3], atol=1e-6)
            if isinstance(a.shape, Box):
                np.testing.assert_allclose(b.shape.size, a.shape.size, rtol=1e-6)
                np.testing.assert_allclose(pb[:3, :3], pa[:3, :3], atol=1e-6)
            elif isinstance(a.shape, Cylinder | Capsule):  # symmetric about z
                np.testing.assert_allclose(pb[:3, 2], pa[:3, 2], atol=1e-6)
                assert b.shape.radius == pytest.approx(a.shape.radius, rel=1e-6)
                assert b.shape.length == pytest.approx(a.shape.length, rel=1e-6)
            elif isinstance(a.shape, Sphere):
                assert b.shape.radius == pytest.approx(a.shape.radius, rel=1e-6)
    assert Box in seen


def test_a_body_without_mass_is_said_to_be_computed_by_the_engine():
    robot, _ = read_description(asset("ant_mjcf"))
    torso = robot.link("torso")
    assert torso.inertial is None
    assert torso.implicit is not None and torso.implicit.source == "colliders"
    assert torso.implicit.mass is None  # the engine computes the mass too
    # MuJoCo's geom density (ant.xml: 5) carried onto each collision
    assert {c.density for c in torso.collisions} == {5.0}


@pytest.mark.parametrize("suffix", [".usdc", ".usd", ".usdz"])
def test_binary_and_packaged_assets_read_as_the_text_ones(tmp_path, suffix):
    from pxr import Usd, UsdUtils

    flat = Usd.Stage.Open(str(asset("spirit40"))).Flatten()
    target = tmp_path / f"spirit40{suffix}"
    if suffix == ".usdz":
        crate = tmp_path / "flat.usdc"
        flat.Export(str(crate))
        assert UsdUtils.CreateNewUsdzPackage(str(crate), str(target))
    else:
        flat.Export(str(target))
    got, _ = read_description(target)
    want, _ = read_description(asset("spirit40"))
    assert [lk.name for lk in got.links] == [lk.name for lk in want.links]
    for a, b in zip(got.links, want.links, strict=True):
        assert a.inertial == b.inertial
        assert len(a.collisions) == len(b.collisions)
