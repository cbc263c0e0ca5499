"""link/shell_voxels.py: the voxel estimate of a wall against exact shells; its stated
error must cover the actual one."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from urdfinertia.body.shell_voxels import voxel_shell
from urdfinertia.inertia import shell


def _check(found: shell.Shell, wall: float, interior: float) -> float:
    actual = abs(found.wall[0] - wall) / wall
    assert actual <= found.error
    assert found.wall[0] + found.interior[0] == pytest.approx(wall + interior, rel=1e-9)
    return actual


@pytest.mark.parametrize("mesh", [
    trimesh.creation.icosphere(subdivisions=4, radius=0.04),
    trimesh.creation.cylinder(radius=0.025, height=0.08, sections=96),
    trimesh.creation.box(extents=[0.07, 0.05, 0.03]),
])
def test_against_the_exact_offset(mesh: trimesh.Trimesh) -> None:
    """Meshes whose exact offset is valid (icosphere: within its stated ~1e-5)."""
    reference = shell.mesh_shell(mesh.vertices, mesh.faces, 0.002)
    found = voxel_shell(mesh.vertices, mesh.faces, 0.002)
    actual = _check(found, reference.wall[0], reference.interior[0])
    assert actual < 0.08
    assert "voxel estimate" in found.method


def test_a_thin_plate_beside_a_box_is_all_wall() -> None:
    """Two bodies: a box (exact shell) and a 1.5 mm plate beside it, which no 2 mm wall
    fits inside: the exact offset is refused, the voxels count the plate as wall."""
    box = trimesh.creation.box(extents=[0.06, 0.05, 0.04])
    plate = trimesh.creation.box(extents=[0.05, 0.04, 0.0015])
    plate.apply_translation([0.0, 0.0, 0.03])
    vertices = np.vstack([box.vertices, plate.vertices])
    faces = np.vstack([box.faces, plate.faces + len(box.vertices)])
    with pytest.raises(shell.ShellError):
        shell.mesh_shell(vertices, faces, 0.002)
    found = voxel_shell(vertices, faces, 0.002)
    exact = shell.box_shell([0.06, 0.05, 0.04], 0.002)
    _check(found, exact.wall[0] + plate.volume, exact.interior[0])


def test_nothing_deep_enough() -> None:
    plate = trimesh.creation.box(extents=[0.05, 0.04, 0.003])
    with pytest.raises(shell.ShellError, match="all wall"):
        voxel_shell(plate.vertices, plate.faces, 0.002)


def test_an_ellipsoid_beyond_the_tube_integral_goes_to_voxels() -> None:
    """The voxel path for ellipsoids, against the tube integral where both apply; and a
    flat ellipsoid (curvature radius 0.72 mm under a 2 mm wall) estimated, not solid."""
    from pathlib import Path

    from urdfinertia.body.parts import Walls, _ellipsoid_on_voxels, shell_solids
    from urdfinertia.descriptions.model import Ellipsoid
    from urdfinertia.inertia import primitives

    radii = (0.05, 0.04, 0.03)
    tube = shell.ellipsoid_shell(radii, 0.004)
    voxels = _ellipsoid_on_voxels(Ellipsoid(radii), 0.004, primitives.ellipsoid(radii, 1.0))
    assert abs(voxels.wall[0] / tube.wall[0] - 1) <= voxels.error
    (flat,) = shell_solids(Ellipsoid((0.05, 0.05, 0.006)), Walls(0.002, 0.0), None,  # type: ignore[arg-type]
                           Path("."))
    assert "voxel estimate" in flat.method
    assert any("tube integral refused" in note for note in flat.notes)
    assert flat.unit.mass < primitives.ellipsoid((0.05, 0.05, 0.006), 1.0).mass


def test_a_large_mesh_offset_is_cross_checked_on_voxels() -> None:
    """Over 2000 faces only a sample of vertices is depth-checked: the offset's wall must
    then agree with a coarse voxel estimate. A right one does; a wrong one is refused."""
    from urdfinertia.body.parts import _cross_check

    ico = trimesh.creation.icosphere(subdivisions=4, radius=0.05)  # 5120 faces
    assert len(ico.faces) > shell.CHECKED_FACES
    found = shell.mesh_shell(ico.vertices, ico.faces, 0.002)
    _cross_check(found, ico.vertices, ico.faces, 0.002)
    v, first, second = found.wall
    wrong = shell.Shell((1.5 * v, 1.5 * first, 1.5 * second), found.interior, 0.0, "wrong")
    with pytest.raises(shell.ShellError, match="outside a voxel estimate"):
        _cross_check(wrong, ico.vertices, ico.faces, 0.002)
