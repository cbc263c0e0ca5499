"""render/scene.py: equivalent-inertia boxes and display meshes."""

from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.model import Inertial, Origin
from urdfinertia.descriptions.urdf.read import robot_from_bytes
from urdfinertia.inertia import primitives
from urdfinertia.render.scene import (
    box_lengths,
    build_scene,
    decimate,
    equivalent_box,
    existing_mass_properties,
    used_only,
)


def random_rotation(rng) -> np.ndarray:
    return Rotation.random(random_state=int(rng.integers(1 << 31))).as_matrix()


def random_pose(rng) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = random_rotation(rng)
    t[:3, 3] = rng.normal(size=3)
    return t


def box_corners(size, pose) -> np.ndarray:
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    local = signs * (0.5 * np.asarray(size))
    return local @ pose[:3, :3].T + pose[:3, 3]


def same_point_sets(a: np.ndarray, b: np.ndarray, atol: float) -> bool:
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return bool(np.all(d.min(axis=1) < atol) and np.all(d.min(axis=0) < atol))


# --- boxes --------------------------------------------------------------------------------
@pytest.mark.parametrize("size", [(0.1, 0.2, 0.3), (1.0, 1.0, 1.0), (0.02, 0.5, 0.5)])
def test_box_lengths_give_back_a_box(size):
    body = primitives.box(size, 2700.0)
    moments, axes = body.principal()
    lengths, clipped = box_lengths(moments, body.mass)
    assert not clipped
    # Axes of a box are the coordinate axes (in some order): map lengths back to x, y, z.
    along = np.abs(axes).argmax(axis=0)
    np.testing.assert_allclose(lengths[np.argsort(along)], size, rtol=1e-12)


def test_box_lengths_clip_and_flag_a_broken_triangle_inequality():
    lengths, clipped = box_lengths(np.array([1.0, 1.0, 3.0]), 2.0)
    assert clipped
    assert lengths[2] == 0.0 and np.all(lengths[:2] > 0)


def test_box_lengths_of_a_flat_body_are_not_flagged():
    lengths, clipped = box_lengths(primitives.box((0.3, 0.2, 1e-9), 1.0).principal()[0], 1.0)
    assert not clipped


def test_box_lengths_refuse_bad_input():
    with pytest.raises(ValueError):
        box_lengths(np.ones(2), 1.0)
    with pytest.raises(ValueError):
        box_lengths(np.ones(3), 0.0)


def test_equivalent_box_of_a_posed_box_is_that_box(rng):
    # A box body placed in the link frame, and the link placed in the world: the
    # equivalent box must coincide with the body's own corners in the world.
    for _ in range(10):
        size = rng.uniform(0.05, 1.0, 3)
        in_link = random_pose(rng)
        link_pose = random_pose(rng)
        body = primitives.box(size, 1000.0).transformed(in_link)
        box = equivalent_box(body, link_pose, "l", "recomputed")
        corners, faces = box.triangles()
        expected = box_corners(size, link_pose @ in_link)
        assert same_point_sets(corners, expected, atol=1e-9)
        assert faces.shape == (12, 3) and set(faces.ravel()) == set(range(8))


def test_box_triangles_are_closed_and_outward(rng):
    box = equivalent_box(primitives.box((0.3, 0.2, 0.1), 1.0), random_pose(rng), "l", "x")
    corners, faces = box.triangles()
    mesh = trimesh.Trimesh(corners, faces, process=False)
    assert mesh.is_watertight
    assert mesh.volume == pytest.approx(0.3 * 0.2 * 0.1, rel=1e-9)  # positive: outward


def test_box_edges_are_the_twelve_edges():
    box = equivalent_box(primitives.box((0.3, 0.2, 0.1), 1.0), np.eye(4), "l", "x")
    lines = box.edge_polyline().reshape(12, 3, 3)
    assert np.all(np.isnan(lines[:, 2]))
    lengths = sorted(np.linalg.norm(lines[:, 1] - lines[:, 0], axis=1))
    np.testing.assert_allclose(lengths, [0.1] * 4 + [0.2] * 4 + [0.3] * 4, rtol=1e-12)


# --- existing inertials -------------------------------------------------------------------
def inertial(mass=2.0, diag=(0.1, 0.2, 0.25), ixy=0.0, rpy=(0.0, 0.0, 0.0)) -> Inertial:
    return Inertial(Origin((0.1, 0.0, 0.0), rpy), mass, diag[0], ixy, 0.0, diag[1], 0.0,
                    diag[2])


def test_existing_mass_properties_rotates_into_the_link_frame():
    mp, why = existing_mass_properties(inertial(rpy=(0.0, 0.0, np.pi / 2)))
    assert why == ""
    np.testing.assert_allclose(np.diag(mp.inertia), [0.2, 0.1, 0.25], atol=1e-12)


@pytest.mark.parametrize("bad, reason", [
    (inertial(mass=0.0), "not positive"),
    (inertial(mass=float("nan")), "non-finite"),
    (inertial(diag=(0.1, 0.1, 0.1), ixy=0.5), "positive semi-definite"),
    (None, "no <inertial>"),
])
def test_existing_mass_properties_reports_invalid_values(bad, reason):
    mp, why = existing_mass_properties(bad)
    assert mp is None and reason in why


def test_existing_tensor_breaking_the_triangle_inequality_still_gets_a_flagged_box():
    mp, _ = existing_mass_properties(inertial(diag=(0.1, 0.1, 0.5)))
    assert mp is not None
    assert equivalent_box(mp, np.eye(4), "l", "existing").clipped


# --- display meshes -----------------------------------------------------------------------
def test_decimate_meets_the_budget():
    sphere = trimesh.creation.icosphere(subdivisions=4)  # 5120 faces
    v, f, method = decimate(sphere.vertices, sphere.faces, 500)
    assert method == "quadric decimation"
    assert 0 < len(f) <= 750
    assert f.max() < len(v)
    # Still the same sphere: every kept vertex lies near the unit sphere.
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, atol=0.1)


def test_decimate_falls_back_to_a_face_subset(monkeypatch):
    def broken(self, *args, **kwargs):
        raise RuntimeError("no decimation here")

    monkeypatch.setattr(trimesh.Trimesh, "simplify_quadric_decimation", broken)
    sphere = trimesh.creation.icosphere(subdivisions=3)
    v, f, method = decimate(sphere.vertices, sphere.faces, 100)
    assert method.startswith("face subset") and len(f) == 100


def test_small_meshes_are_kept_as_they_are():
    box = trimesh.creation.box()
    v, f, method = decimate(box.vertices, box.faces, 100)
    assert method == "as is" and len(f) == 12


SCENE_URDF = """<robot name="s">
  <link name="base"><visual><origin xyz="0 0 0.5"/><geometry><box size="1 2 1"/></geometry>
    </visual></link>
  <link name="arm">
    <visual><origin xyz="0.1 0 0"/><geometry><mesh filename="ball.stl" scale="2 2 2"/>
    </geometry></visual>
    <collision><geometry><cylinder radius="0.1" length="0.4"/></geometry></collision>
  </link>
  <link name="tip"><collision><geometry><mesh filename="missing.stl"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 3" rpy="0 0 1.5707963267948966"/></joint>
  <joint name="j2" type="fixed"><parent link="arm"/><child link="tip"/></joint>
</robot>"""


def scene_robot(tmp_path: Path):
    trimesh.creation.icosphere(subdivisions=4, radius=0.1).export(tmp_path / "ball.stl")
    path = tmp_path / "s.urdf"
    path.write_text(SCENE_URDF)
    return robot_from_bytes(SCENE_URDF.encode(), path)


def test_build_scene_places_geometry_at_the_zero_configuration(tmp_path):
    scene = build_scene(scene_robot(tmp_path), MeshLibrary(), face_budget=400)
    by_link = {m.link: m for m in scene.meshes}
    assert set(by_link) == {"base", "arm"}
    base = by_link["base"].vertices
    np.testing.assert_allclose(base.min(axis=0), [-0.5, -1.0, 0.0], atol=1e-6)
    np.testing.assert_allclose(base.max(axis=0), [0.5, 1.0, 1.0], atol=1e-6)
    arm = by_link["arm"]
    # Sphere of radius 0.1 scaled by 2, at x = 0.1 in the arm frame, which is yawed by 90
    # degrees and 3 m up: its centre lands at (0, 0.1, 3).
    centre = (arm.vertices.min(axis=0) + arm.vertices.max(axis=0)) / 2
    np.testing.assert_allclose(centre, [0.0, 0.1, 3.0], atol=0.01)
    np.testing.assert_allclose(np.linalg.norm(arm.vertices - centre, axis=1), 0.2, atol=0.02)
    assert arm.source_faces == 5120 and len(arm.faces) <= 600
    assert arm.vertices.dtype == np.float32 and arm.faces.dtype == np.int32
    assert any("'tip'" in n and "not drawn" in n for n in scene.notes)


def test_build_scene_collision_view_uses_collision_geometry(tmp_path):
    scene = build_scene(scene_robot(tmp_path), MeshLibrary(), view="collision")
    arm = next(m for m in scene.meshes if m.link == "arm")
    assert arm.method == "primitive" and arm.label.startswith("collision")
    # The base has no collision: its visual is drawn instead.
    assert any(m.link == "base" and m.label.startswith("visual") for m in scene.meshes)


def test_build_scene_refuses_an_unknown_view(tmp_path):
    with pytest.raises(ValueError):
        build_scene(scene_robot(tmp_path), MeshLibrary(), view="pretty")



def test_display_meshes_keep_only_distinct_used_vertices(rng):
    """A triangle soup (every corner its own vertex) plus unused points shrinks to the
    sphere's own vertices, and every face keeps its corner positions."""
    sphere = trimesh.creation.icosphere(2)
    soup = sphere.vertices[sphere.faces].reshape(-1, 3)
    stray = rng.uniform(5.0, 6.0, size=(100, 3))
    v = np.concatenate([stray, soup])
    f = len(stray) + np.arange(len(soup)).reshape(-1, 3)
    small_v, small_f = used_only(v, f)
    assert len(small_v) == len(sphere.vertices)
    np.testing.assert_array_equal(small_v[small_f], v[f])
    _, dec_f, _ = decimate(v, f, 10_000)  # under budget: as is, but compacted too
    assert dec_f.max() == len(sphere.vertices) - 1


def test_a_cone_is_drawn_centred_with_its_apex_up():
    # the model's cone is centred on its origin, apex at +length/2 (USD's convention)
    from urdfinertia.descriptions.model import Cone
    from urdfinertia.render.scene import primitive_triangles

    vertices, faces = primitive_triangles(Cone(radius=0.1, length=0.4))
    assert vertices[:, 2].min() == pytest.approx(-0.2)
    assert vertices[:, 2].max() == pytest.approx(0.2)
    top = vertices[vertices[:, 2] > 0.2 - 1e-12]
    assert np.allclose(top[:, :2], 0.0)  # the apex is on the axis
    base = vertices[vertices[:, 2] < -0.2 + 1e-12]
    assert np.hypot(base[:, 0], base[:, 1]).max() == pytest.approx(0.1)
    assert faces.max() < len(vertices)


# Closed forms of the volumes; a drawn round primitive is inscribed in its shape, so its
# volume is a little smaller: with 24 segments a circle keeps sin(2 pi/24) 24/(2 pi) =
# 98.9 % of its area, and the 12 rings of a sphere lose about as much again.
_PRIMITIVES = [
    ("box", lambda m: m.Box(size=(0.3, 0.2, 0.1)), 0.3 * 0.2 * 0.1, 1.0),
    ("cylinder", lambda m: m.Cylinder(radius=0.1, length=0.4), np.pi * 0.01 * 0.4, 0.985),
    ("cone", lambda m: m.Cone(radius=0.1, length=0.4), np.pi * 0.01 * 0.4 / 3, 0.985),
    ("sphere", lambda m: m.Sphere(radius=0.2), 4 / 3 * np.pi * 0.2 ** 3, 0.96),
    ("ellipsoid", lambda m: m.Ellipsoid(radii=(0.1, 0.2, 0.3)),
     4 / 3 * np.pi * 0.1 * 0.2 * 0.3, 0.96),
    ("capsule", lambda m: m.Capsule(radius=0.1, length=0.3),
     np.pi * 0.01 * 0.3 + 4 / 3 * np.pi * 0.1 ** 3, 0.96),
]


@pytest.mark.parametrize(("name", "make", "volume", "least"), _PRIMITIVES,
                         ids=[p[0] for p in _PRIMITIVES])
def test_primitives_are_closed_outward_and_inscribed(name, make, volume, least):
    from urdfinertia.descriptions import model
    from urdfinertia.render.scene import primitive_triangles

    vertices, faces = primitive_triangles(make(model))
    mesh = trimesh.Trimesh(vertices, faces, process=False)  # an independent judge
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert least * volume <= mesh.volume <= volume * (1 + 1e-12)  # positive: outward
    assert faces.min() == 0 and faces.max() == len(vertices) - 1  # no stray vertex


def test_revolved_refuses_a_profile_without_a_ring():
    from urdfinertia.render.scene import revolved

    with pytest.raises(ValueError, match="shape"):
        revolved(np.array([[0.0, 0.0], [0.0, 1.0]]))


def test_primitives_need_no_mesh_library():
    # a warm report draws its primitives without importing trimesh (seconds of imports)
    import subprocess
    import sys

    code = ("import sys\nfrom urdfinertia.descriptions.model import Sphere\n"
            "from urdfinertia.render.scene import primitive_triangles\n"
            "primitive_triangles(Sphere(radius=1.0))\nprint('trimesh' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"
