"""The geometry a derived inertial integrates (``--geometry auto``, per link), and that a
placeholder is never left silently."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.body.geometry_choice import DENSE, Candidate, choose
from urdfinertia.body.options import FixOptions, weighable
from urdfinertia.cli import main
from urdfinertia.descriptions.model import Box, GeometryRef, Mesh, Origin
from urdfinertia.plan.fix import fix_file
from urdfinertia.plan.results import Status

DATA = Path(__file__).parents[1] / "data" / "geometry"


def _candidate(role: str, kind: str, volume: float, centroid=(0.0, 0.0, 0.0),
               diagonal: float = 1.0, dropped: tuple = ()) -> Candidate:
    return Candidate(role, (), (), dropped, kind, volume, np.asarray(centroid, float),
                     diagonal)


def test_mesh_over_primitive_stand_in():
    stand_in = _candidate("collision", "primitive", 1e-3)
    mesh = _candidate("visual", "mesh", 1.2e-3)
    best, why = choose([stand_in, mesh], mass=2.0, com=np.zeros(3))
    assert best is mesh
    assert why.role == "visual" and why.kind == "mesh"
    assert "detailed mesh over primitive stand-ins" in why.why
    assert why.others == ("collision (primitive stand-ins)",)
    assert why.density == pytest.approx(2.0 / 1.2e-3)


def test_detailed_mesh_over_hull():
    hull = _candidate("collision", "hull", 1e-3)
    mesh = _candidate("visual", "mesh", 0.8e-3)
    assert choose([hull, mesh], 2.0, np.zeros(3))[0] is mesh


def test_implausible_density_loses_to_any_plausible_one():
    # 2 kg in 1 cm^3: no material; the stand-in box holds the body's mass plausibly
    marker = _candidate("visual", "mesh", 1e-6)
    box = _candidate("collision", "primitive", 1e-3)
    best, why = choose([marker, box], 2.0, np.zeros(3))
    assert best is box
    assert "implied density plausible" in why.why


def test_a_set_denser_than_titanium_loses_to_one_a_link_can_be_made_of():
    # 2 kg in 0.25 l (8000 kg/m^3): the mesh is short of the body's volume
    thin = _candidate("visual", "mesh", 2.5e-4)
    box = _candidate("collision", "primitive", 1e-3)
    best, why = choose([thin, box], 2.0, np.zeros(3))
    assert best is box and why.why == f"implied density at most {DENSE:.0f} kg/m³"
    # at 4000 kg/m^3 the mesh stays the more faithful kind
    solid = _candidate("visual", "mesh", 5e-4)
    assert choose([solid, box], 2.0, np.zeros(3))[0] is solid
    # every set dense: nothing to prefer on that ground
    denser = _candidate("collision", "primitive", 2e-4)
    assert choose([thin, denser], 2.0, np.zeros(3))[0] is thin


def test_fix_uses_the_stand_in_where_the_mesh_misses_volume():
    result = fix_file(DATA / "dense.urdf", FixOptions())
    forearm = result.link("forearm")
    # the L-shaped bar (1.152 l) would hold 10 kg at 8681 kg/m^3; the box (4.5 l) at 2222
    assert forearm.status == Status.RECOMPUTED and forearm.geometry == "collision"
    assert forearm.choice is not None and forearm.choice.kind == "primitive"
    assert forearm.choice.density == pytest.approx(10 / 4.5e-3)
    assert "implied density at most 4500 kg/m³" in forearm.choice.why
    assert forearm.choice.others == ("visual (detailed mesh)",)


def test_centroid_nearest_the_kept_com_among_the_same_kind():
    far = _candidate("collision", "mesh", 1e-3, centroid=(0.3, 0, 0))
    near = _candidate("visual", "mesh", 1e-3, centroid=(0.01, 0, 0))
    best, why = choose([far, near], 2.0, np.zeros(3))
    assert best is near and why.why == "centroid nearest the kept CoM"
    assert why.offset == pytest.approx(0.01)
    # a far centroid does not hand the choice to a less faithful kind (measured worse)
    box = _candidate("collision", "primitive", 1e-3, centroid=(0.05, 0, 0))
    assert choose([far, box], 2.0, np.zeros(3))[0] is far


def test_a_centroid_on_the_kept_com_says_the_tensor_came_from_that_geometry():
    on = _candidate("collision", "primitive", 1e-3, centroid=(1e-5, 0, 0))
    mesh = _candidate("visual", "mesh", 1e-3, centroid=(0.02, 0, 0))
    best, why = choose([mesh, on], 2.0, np.zeros(3))
    assert best is on and why.why == "centroid on the kept CoM"


def test_a_whole_set_beats_one_with_an_element_dropped():
    partial = _candidate("visual", "mesh", 1e-3, dropped=("x",))
    whole = _candidate("collision", "primitive", 1e-3)
    assert choose([partial, whole], 2.0, np.zeros(3))[0] is whole


def test_massless_geoms_keep_their_shape_without_their_weights():
    o = Origin((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    shown = GeometryRef("visual", 0, None, o, Mesh("a.stl"), density=0.0, relative=True)
    other = GeometryRef("visual", 1, None, o, Box((1.0, 1.0, 1.0)), density=500.0)
    out = weighable((shown, other))
    assert all(r.density is None and r.mass is None and not r.relative for r in out)
    assert weighable((other,)) == (other,)


def test_visual_only_geoms_make_the_inertial_and_a_placeholder_is_never_left_silently():
    result = fix_file(DATA / "visual_only.xml", FixOptions())
    forearm, hand, tool = (result.link(n) for n in ("forearm", "hand", "tool"))
    # density="0", contype=conaffinity=0, group 2: still the body's shape
    assert forearm.status == Status.RECOMPUTED and forearm.geometry == "visual"
    assert forearm.choice is not None and forearm.choice.kind == "mesh"
    # the hand's colliding capsule would put 2 kg in 0.06 l: the visual mesh is the body
    assert hand.status == Status.RECOMPUTED and hand.geometry == "visual"
    assert hand.choice is not None and "implied density plausible" in hand.choice.why
    # the L-shaped bar's tensor about the kept CoM's own centroid: closed form of two
    # boxes (0.3 x 0.06 x 0.04 and 0.06 x 0.06 x 0.12) at 2 kg spread by volume
    t = forearm.assembly.total
    v1, v2 = 0.3 * 0.06 * 0.04, 0.06 * 0.06 * 0.12
    m1, m2 = 2.0 * v1 / (v1 + v2), 2.0 * v2 / (v1 + v2)
    c1, c2 = np.array([0.15, 0, 0]), np.array([0.27, 0, 0.08])
    c = (m1 * c1 + m2 * c2) / 2.0

    def box(m, size):
        a, b, d = size
        return m / 12 * np.diag([b * b + d * d, a * a + d * d, a * a + b * b])

    def shift(m, r):
        return m * (r @ r * np.eye(3) - np.outer(r, r))

    expected = box(m1, (0.3, 0.06, 0.04)) + shift(m1, c1 - c) + \
        box(m2, (0.06, 0.06, 0.12)) + shift(m2, c2 - c)
    np.testing.assert_allclose(t.inertia, expected, rtol=1e-6, atol=1e-12)
    # nothing at all to derive the tool from, and a placeholder is no value to keep: the
    # smallest honest body, a solid sphere of its 0.5 kg at 1000 kg/m^3, said so
    assert tool.status == Status.REPAIRED and "placeholder-inertia" in tool.why
    radius = (3 * 0.5 / (4 * np.pi * 1000.0)) ** (1 / 3)
    np.testing.assert_allclose(tool.after.inertia, 0.4 * 0.5 * radius ** 2 * np.eye(3),
                               rtol=1e-12)
    assert any("solid sphere" in f.message for f in tool.findings)
    assert result.left == ()


def test_fix_cli_says_the_placeholder_repair_and_which_geometry(tmp_path, capsys):
    out, js = tmp_path / "out.xml", tmp_path / "out.json"
    code = main(["fix", str(DATA / "visual_only.xml"), "-o", str(out), "--json", str(js)])
    assert code == 0
    doc = json.loads(js.read_text())
    assert doc["links_left"] == []
    links = {x["link"]: x for x in doc["links"]}
    assert links["forearm"]["geometry_choice"]["role"] == "visual"
    assert links["forearm"]["error_bar"]["kind"] == "mesh"
    assert links["tool"]["status"] == "repaired"
    assert any("a solid sphere of the mass" in f["message"]
               for f in links["tool"]["findings"])


def test_forced_geometry_is_used_as_asked():
    result = fix_file(DATA / "visual_only.xml", FixOptions(geometry="collision",
                                                           recompute="links",
                                                           links=("hand",)))
    hand = result.link("hand")
    assert hand.geometry == "collision" and hand.choice is not None
    assert hand.choice.kind == "primitive" and hand.choice.why == "the only geometry"
