"""The author's conventions (``judge.conventions``), inferred from all links jointly.

A hand-made robot of CAD-like links (a trunk, two four-link arms and a four-link leg, each
link a turned box with a CAD tensor near the box's own) is written with one convention
planted: in every link, or in one arm only, or in one link only. The planted edit must be
undone exactly where it was planted, on every link it was planted in, and nowhere else.
"""

from __future__ import annotations

import numpy as np
import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import robot_from_bytes
from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.judge.conventions import chains
from urdfinertia.plan.fix import verdicts
from urdfinertia.plan.results import Action

ARMS = {"left": ("l_shoulder", "l_upper", "l_elbow", "l_forearm"),
        "right": ("r_shoulder", "r_upper", "r_elbow", "r_forearm"),
        "leg": ("hip", "thigh", "shin", "foot")}


def _box_tensor(size: np.ndarray, mass: float) -> np.ndarray:
    a, b, c = size ** 2
    return mass / 12 * np.diag([b + c, a + c, a + b])


def cad_links(seed: int = 3) -> dict[str, dict]:
    """Per link: its box (size, xyz, rpy) and CAD values (mass, com, tensor about the CoM
    in link axes) that differ from the box's own as a CAD body differs from its stand-in."""
    rng = np.random.default_rng(seed)
    out = {"trunk": None}
    names = ["trunk", *[n for chain in ARMS.values() for n in chain]]
    for name in names:
        size = rng.uniform(0.04, 0.12, 3)
        size[2] = rng.uniform(0.2, 0.3)  # long along z, as a limb
        xyz = np.array([rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), size[2] / 2
                        + rng.uniform(0.02, 0.05)])
        rpy = rng.uniform(-0.5, 0.5, 3)
        mass = float(np.prod(size) * rng.uniform(1800, 2800))
        rot = rpy_matrix(rpy)
        body = _box_tensor(size * rng.uniform(0.9, 1.1, 3), mass)
        tensor = rot @ body @ rot.T
        com = xyz + rng.uniform(-0.005, 0.005, 3)
        out[name] = {"size": size, "xyz": xyz, "rpy": rpy, "mass": mass, "com": com,
                     "tensor": tensor}
    return out


def parallel_axis(v: dict) -> np.ndarray:
    c = v["com"]
    return v["tensor"] + v["mass"] * (np.dot(c, c) * np.eye(3) - np.outer(c, c))


def products_negated(v: dict) -> np.ndarray:
    t = -v["tensor"].copy()
    np.fill_diagonal(t, np.diag(v["tensor"]))
    return t


ENTRIES = {"ixx": (0, 0), "ixy": (0, 1), "ixz": (0, 2), "iyy": (1, 1), "iyz": (1, 2),
           "izz": (2, 2)}


def _num(x: float) -> str:
    return repr(float(x))


def urdf(values: dict[str, dict], planted: dict[str, str]) -> bytes:
    """The robot with ``planted[link]`` (an edit name) made in those links' values."""
    parts = ['<robot name="conventions">']
    for name, v in values.items():
        mass, tensor = v["mass"], v["tensor"]
        edit = planted.get(name)
        if edit == "parallel axis":
            tensor = parallel_axis(v)
        elif edit == "products":
            tensor = products_negated(v)
        elif edit == "grams":
            mass, tensor = mass * 1000, tensor * 1000
        elif edit == "mass in grams":
            mass = mass * 1000
        elif edit == "kg mm2":
            tensor = tensor * 1e6
        t = tensor
        s, xyz, rpy = v["size"], v["xyz"], v["rpy"]
        parts.append(
            f'<link name="{name}"><inertial><origin xyz="{" ".join(map(_num, v["com"]))}"/>'
            f'<mass value="{_num(mass)}"/><inertia '
            + " ".join(f'{k}="{_num(t[i, j])}"' for k, (i, j) in ENTRIES.items()) + '/>'
            f'</inertial><collision><origin xyz="{" ".join(map(_num, xyz))}" '
            f'rpy="{" ".join(map(_num, rpy))}"/><geometry><box size="'
            f'{" ".join(map(_num, s))}"/></geometry></collision></link>')
    for chain in ARMS.values():
        for parent, child in zip(("trunk", *chain[:-1]), chain, strict=True):
            parts.append(f'<joint name="{child}_joint" type="revolute"><parent link="{parent}"/>'
                         f'<child link="{child}"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>'
                         '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>')
    parts.append("</robot>")
    return "\n".join(parts).encode()


def judged(planted: dict[str, str]) -> dict:
    values = cad_links()
    robot = robot_from_bytes(urdf(values, planted), "conventions.urdf")
    found = verdicts(robot, FixOptions(), MeshLibrary())
    return {r.name: r for r in found.links}, found, values


EVERY = [n for n in cad_links() if n != "trunk"]


def test_the_clean_robot_is_kept():
    links, _, _ = judged({})
    assert {n: r.action for n, r in links.items() if r.action != Action.KEEP} == {}


@pytest.mark.parametrize(("edit", "undo"), [("parallel axis", "parallel axis removed"),
                                             ("products", "products negated"),
                                             ("grams", "mass and tensor x1e-3"),
                                             ("mass in grams", "mass x1e-3"),
                                             ("kg mm2", "tensor x1e-6")])
def test_a_whole_file_convention_is_undone_on_every_link(edit, undo):
    links, found, values = judged({n: edit for n in [*EVERY, "trunk"]})
    for name, v in values.items():
        r = links[name]
        assert r.action == Action.CORRECT, (name, r.decision)
        assert r.slip is not None and r.slip.edit == undo, (name, r.slip)
        after = r.after
        assert after is not None
        assert after.mass == pytest.approx(v["mass"], rel=1e-9)
        np.testing.assert_allclose(after.inertia, v["tensor"], rtol=1e-9, atol=1e-12)
    said = [f.message for f in found.findings if f.code == "convention-inferred"]
    assert len(said) == 1 and "(in the chain" not in said[0], said


def test_a_convention_of_one_limb_is_undone_on_that_limb_alone():
    """The left arm written about its joints, the rest about the CoM: the file as a whole
    contradicts the convention, the arm's chain supports it."""
    links, found, values = judged({n: "parallel axis" for n in ARMS["left"]})
    for name in ARMS["left"]:
        r = links[name]
        assert r.action == Action.CORRECT and r.slip is not None, (name, r.decision)
        assert r.slip.edit == "parallel axis removed"
        np.testing.assert_allclose(r.after.inertia, values[name]["tensor"], rtol=1e-9,
                                   atol=1e-12)
    assert all(links[n].action == Action.KEEP for n in values if n not in ARMS["left"])
    said = [f.message for f in found.findings if f.code == "convention-inferred"]
    assert len(said) == 1 and "(in the chain from l_shoulder)" in said[0], said


def test_one_link_is_no_convention():
    """A single link about its joint is that link's slip, if its geometry shows it, never
    a convention for its neighbours."""
    links, found, _ = judged({"l_upper": "parallel axis"})
    assert not [f for f in found.findings if f.code == "convention-inferred"]
    assert all(links[n].action == Action.KEEP for n in links if n != "l_upper")


def test_chains_run_between_branching_links():
    edges = [("base", "a1"), ("a1", "a2"), ("a2", "a3"), ("base", "b1"), ("b1", "b2"),
             ("b2", "c1"), ("b2", "d1"), ("d1", "d2")]
    assert sorted(chains(edges)) == [["a1", "a2", "a3"], ["b1", "b2"], ["c1"], ["d1", "d2"]]
    assert chains([("world", "base"), ("base", "l1"), ("l1", "l2")]) == [["base", "l1", "l2"]]


def test_chains_end_at_a_cycle():
    """A joint whose child is its own parent (a fuzzed SDF) ends the chain, in bounded
    time and memory."""
    assert chains([("base", "a"), ("a", "b"), ("b", "b")]) == [["a", "b"]]
    assert chains([("base", "a"), ("a", "b"), ("b", "a")]) == [["a", "b"]]
