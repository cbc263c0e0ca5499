"""priors/structure.py: a structure prior's parts sum to the link's mass with its kept CoM."""

import numpy as np
import pytest

from urdfinertia.inertia import primitives
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.priors.data import PriorTable
from urdfinertia.priors.features import JointAxis, LinkFeatures
from urdfinertia.priors.structure import model_parts, prior_body, structure_prior

#: a 0.4 x 0.1 x 0.1 m bar at unit mass, its centroid off the link origin
HOUSING = primitives.box((0.4, 0.1, 0.1), 1.0).with_mass(1.0).translated((0.2, 0.0, 0.0))
AXES = (JointAxis("shoulder", "parent", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
        JointAxis("elbow", "child", (0.4, 0.0, 0.0), (0.0, 1.0, 0.0)))
MASS = 3.0
COM = np.array([0.17, 0.01, -0.004])  # the kept CoM, off the centroid
DIAGONAL = float(np.linalg.norm([0.4, 0.1, 0.1]))

MODELS = [
    {"model": "homogeneous"},
    {"model": "actuators", "share": 0.2, "radius": 0.1, "ends": ["parent", "child"],
     "hold": "housing"},
    {"model": "actuators", "share": 0.1, "radius": 0.05, "ends": ["child"], "hold": "rigid"},
    {"model": "actuators", "share": 0.6, "radius": 0.05, "ends": ["parent", "child"],
     "hold": "housing", "max_share": 0.8},
    {"model": "core", "share": 0.4, "scale": 0.5},
    {"model": "shell", "scale": 0.8},
]


def parts_of(cell):
    return model_parts(cell, centroid=HOUSING.com, com=COM, diagonal=DIAGONAL, axes=AXES)


@pytest.mark.parametrize("cell", MODELS, ids=lambda c: f"{c['model']}-{c.get('hold', '')}")
def test_parts_sum_to_the_mass_with_the_kept_com(cell):
    parts = parts_of(cell)
    assert sum(p.share for p in parts) == pytest.approx(1.0, abs=1e-12)
    body = prior_body(parts, HOUSING, MASS)
    assert body.mass == pytest.approx(MASS, rel=1e-12)
    np.testing.assert_allclose(body.com, COM, atol=1e-12)
    assert np.linalg.eigvalsh(body.inertia)[0] > 0


def test_actuators_stay_on_their_axes_when_the_housing_holds_the_com():
    parts = parts_of(MODELS[1])
    assert [p.name for p in parts] == ["housing", "actuator 'shoulder'", "actuator 'elbow'"]
    np.testing.assert_allclose(parts[1].position, AXES[0].point)
    np.testing.assert_allclose(parts[2].position, AXES[1].point)
    assert parts[1].shape == "cylinder" and parts[1].axis == (0.0, 0.0, 1.0)
    assert parts[1].radius == pytest.approx(0.1 * DIAGONAL)
    # rigid: every part moves by the same offset, so the actuators leave their axes
    rigid = parts_of(MODELS[2])
    offset = np.asarray(rigid[0].position) - HOUSING.com
    np.testing.assert_allclose(rigid[1].position, np.asarray(AXES[1].point) + offset)


def test_the_actuators_share_is_capped():
    parts = parts_of(MODELS[3])  # 60 % each on two joints asked, at most 80 % in all
    assert [p.share for p in parts[1:]] == pytest.approx([0.4, 0.4])
    assert parts[0].share == pytest.approx(0.2)


def test_core_and_shell_scale_the_homogeneous_tensor():
    at_centroid = dict(centroid=HOUSING.com, com=HOUSING.com, diagonal=DIAGONAL, axes=AXES)
    homogeneous = MASS * np.asarray(HOUSING.inertia)
    s, c = 0.4, 0.5
    core = prior_body(model_parts(MODELS[4], **at_centroid), HOUSING, MASS)
    np.testing.assert_allclose(core.inertia, ((1 - s) + s * c ** 2) * homogeneous, rtol=1e-12)
    c = 0.8
    shell = prior_body(model_parts(MODELS[5], **at_centroid), HOUSING, MASS)
    np.testing.assert_allclose(shell.inertia, (1 - c ** 5) / (1 - c ** 3) * homogeneous,
                               rtol=1e-12)
    cavity = model_parts(MODELS[5], **at_centroid)[1]
    assert cavity.name == "cavity" and cavity.share < 0


def test_an_actuator_is_a_solid_cylinder_along_its_axis():
    cell = {"model": "actuators", "share": 0.5, "radius": 0.1, "ends": ["parent"],
            "hold": "housing"}
    parts = model_parts(cell, centroid=np.zeros(3), com=np.zeros(3), diagonal=1.0,
                        axes=(AXES[0],))
    point = MassProperties(1e-9, parts[0].position, np.zeros((3, 3)))  # housing weightless
    body = prior_body(parts[1:], point, 2.0 / 0.5)  # the actuator alone: 2 kg
    expected = primitives.cylinder(0.1, 0.1, 1.0).with_mass(2.0)
    np.testing.assert_allclose(body.inertia, expected.inertia, rtol=1e-12)


def test_a_link_without_moving_joints_keeps_the_homogeneous_body():
    parts = model_parts(MODELS[1], centroid=HOUSING.com, com=COM, diagonal=DIAGONAL, axes=())
    assert [(p.name, p.share) for p in parts] == [("housing", 1.0)]
    body = prior_body(parts, HOUSING, MASS)
    np.testing.assert_allclose(body.inertia, MASS * np.asarray(HOUSING.inertia), rtol=1e-12)


def features(part: str, geometry: str) -> LinkFeatures:
    return LinkFeatures("cobot", part, geometry, "visual", 0.004, 0.5, DIAGONAL, 0.5, 0.3, 2,
                        1.0)


def test_cells_are_looked_up_finest_first():
    table = PriorTable.from_dict({
        "format": "urdfinertia-priors", "version": 1,
        "mass": {"coefficients": {}, "band": {}, "robot_band": {}},
        "structure": {"level": 0.8, "cells": {
            "base/mesh": {"model": "core", "share": 0.2, "scale": 0.5, "band": 0.6},
            "leg": dict(MODELS[1], band=0.4),
            "*": {"model": "homogeneous", "band": 0.9}}}})
    got = {(p, g): structure_prior(features(p, g), centroid=HOUSING.com, com=COM, axes=AXES,
                                   table=table)
           for p, g in (("base", "mesh"), ("base", "hull"), ("leg", "primitive"))}
    assert (got["base", "mesh"].cell, got["base", "mesh"].model) == ("base/mesh", "core")
    assert got["base", "mesh"].band == 0.6 and got["base", "mesh"].level == 0.8
    assert (got["base", "hull"].cell, got["base", "hull"].model) == ("*", "homogeneous")
    assert got["base", "hull"].band == 0.9
    assert (got["leg", "primitive"].cell, got["leg", "primitive"].model) == ("leg",
                                                                           "actuators")
    again = structure_prior(features("leg", "primitive"), centroid=HOUSING.com, com=COM,
                            axes=AXES, table=table)
    assert again == got["leg", "primitive"]  # deterministic, plain data


def test_unknown_models_and_shapes_are_refused():
    with pytest.raises(ValueError, match="unknown structure model"):
        parts_of({"model": "spring"})
    bad = parts_of(MODELS[0])[0].__class__("x", 1.0, (0.0, 0.0, 0.0), "torus")
    with pytest.raises(ValueError, match="unknown part shape"):
        prior_body([bad], HOUSING, MASS)
