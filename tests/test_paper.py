"""Reproduce Szuminski & Kapitaniak (2006) through decomposition specs (eqs. 15-57).

Every expected value is computed here from the paper's formulas (or by direct quadrature of
eq. 22), never by calling the maths under test; the tool is driven the way a user drives
it: a URDF plus a TOML spec, through ``fix``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import load_spec
from urdfinertia.descriptions.urdf.read import read_urdf
from urdfinertia.plan.fix import fix_file

ROOT = Path(__file__).resolve().parents[1]
#: Closed forms and sums of a few terms: only floating-point round-off separates the tool
#: from the formulas, so 1e-12 relative (x the tensor's largest entry for near-zero ones).
RTOL = 1e-12


def toml_vec(v) -> str:
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def run_spec(tmp_path: Path, spec_text: str):
    """A one-link URDF (link 'a', no geometry) fixed with ``spec_text``: its LinkResult."""
    urdf = tmp_path / "one.urdf"
    urdf.write_text('<?xml version="1.0"?>\n<robot name="t">\n  <link name="a">\n  </link>\n'
                    '</robot>\n')
    spec = tmp_path / "one.inertia.toml"
    spec.write_text(spec_text)
    result = fix_file(urdf, FixOptions(spec=load_spec(spec)))
    return result.links[0]


def assert_tensor(actual, expected, rtol=RTOL):
    expected = np.asarray(expected, dtype=float)
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * np.abs(expected).max())


def box_spec(size, density, element_xyz=(0, 0, 0), element_rpy=(0, 0, 0), xyz=(0, 0, 0),
             rpy=(0, 0, 0)) -> str:
    return (f"[links.a.elements.e]\nxyz = {toml_vec(element_xyz)}\nrpy = {toml_vec(element_rpy)}"
            f"\n[links.a.elements.e.parts.p]\nbox = {{ size = {toml_vec(size)} }}\n"
            f"xyz = {toml_vec(xyz)}\nrpy = {toml_vec(rpy)}\ndensity = {float(density)!r}\n")


# --- eq. 34 ---------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(5))
def test_eq34_cube_about_its_centre(tmp_path, seed):
    rng = np.random.default_rng(seed)
    w, rho = rng.uniform(0.01, 1.0), rng.uniform(100.0, 9000.0)
    total = run_spec(tmp_path, box_spec([w, w, w], rho)).assembly.total
    m = rho * w**3
    assert total.mass == pytest.approx(m, rel=RTOL)
    assert_tensor(total.inertia, np.eye(3) * m * w**2 / 6.0)  # B_x = B_y = B_z = m w^2 / 6


# --- eqs. 38, 39 ----------------------------------------------------------------------

def eq39(m, a, b, h):
    return np.diag([m / 12 * (b**2 + h**2), m / 12 * (a**2 + h**2), m / 12 * (a**2 + b**2)])


def eq38(m, a, b, h, r):
    rx, ry, rz = r
    return eq39(m, a, b, h) + np.array([
        [m * (ry**2 + rz**2), -m * rx * ry, -m * rx * rz],
        [-m * rx * ry, m * (rx**2 + rz**2), -m * ry * rz],
        [-m * rx * rz, -m * ry * rz, m * (rx**2 + ry**2)],
    ])


@pytest.mark.parametrize("seed", range(5))
def test_eq39_and_eq38_cuboid_element(tmp_path, seed):
    rng = np.random.default_rng(100 + seed)
    a, b, h = rng.uniform(0.02, 0.5, 3)
    rho = rng.uniform(500.0, 8000.0)
    origin = rng.uniform(-1, 1, 3)  # element frame 0_p in the link frame
    r_c = rng.uniform(-0.2, 0.2, 3)  # the element's centre of gravity in its frame (eq. 1)
    result = run_spec(tmp_path, box_spec([a, b, h], rho, element_xyz=origin, xyz=r_c))
    part = result.assembly.parts[0].mass_properties  # in the link frame
    m = rho * a * b * h
    assert part.mass == pytest.approx(m, rel=RTOL)
    np.testing.assert_allclose(part.com, origin + r_c, rtol=RTOL, atol=1e-15)
    assert_tensor(part.inertia, eq39(m, a, b, h))  # about its own centre
    assert_tensor(part.about(origin), eq38(m, a, b, h, r_c))  # about 0_p (Huygens-Steiner)


# --- eqs. 15-17 and 23-26 -------------------------------------------------------------

def eq17(gamma, alpha, delta):
    """The closed-form matrix A_o of eq. 17, typed from the paper."""
    sa, ca, sd, cd, sg, cg = (np.sin(alpha), np.cos(alpha), np.sin(delta), np.cos(delta),
                              np.sin(gamma), np.cos(gamma))
    return np.array([
        [ca * cd, sa * sg * cd - sd * cg, sa * cd * cg + sd * sg],
        [sd * ca, sa * sd * sg + cd * cg, sa * sd * cg - sg * cd],
        [-sa, sg * ca, ca * cg],
    ])


def test_eq15_17_composed_rotation_of_element_and_part_frames(tmp_path, rng):
    # Random element and part frames; the tool's part pose must be
    # A_o(element) @ A_o(part) with A_o from eq. 17, and the centre maps by eq. 23.
    for i in range(20):
        e_rpy, p_rpy = rng.uniform(-np.pi, np.pi, 3), rng.uniform(-np.pi, np.pi, 3)
        e_xyz, p_xyz = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3)
        spec = box_spec([0.1, 0.2, 0.3], 1000.0, e_xyz, e_rpy, p_xyz, p_rpy)
        folder = tmp_path / str(i)
        folder.mkdir()
        pr = run_spec(folder, spec).assembly.parts[0]
        a_e, a_p = eq17(*e_rpy), eq17(*p_rpy)
        np.testing.assert_allclose(pr.part.pose[:3, :3], a_e @ a_p, atol=1e-14)
        np.testing.assert_allclose(pr.mass_properties.com, e_xyz + a_e @ p_xyz, atol=1e-14)


def _gauss_box_integral(fn, size, density):
    """rho * integral of fn(x, y, z) over a centred box: 2-point Gauss-Legendre per axis,
    exact for the quadratic integrands of eq. 26."""
    nodes = np.array([-1.0, 1.0]) / np.sqrt(3.0)
    half = np.asarray(size) / 2.0
    total = 0.0
    for x in nodes * half[0]:
        for y in nodes * half[1]:
            for z in nodes * half[2]:
                total += fn(x, y, z)
    return density * total * np.prod(half)  # weights are 1; Jacobian prod(half)


def eq26_tensor(gamma, delta, size, density):
    """Eq. 25 with the entries a..f of eq. 26 (alpha = 0) integrated over the box."""
    sd, cd, sg, cg = np.sin(delta), np.cos(delta), np.sin(gamma), np.cos(gamma)

    def a(x, y, z):
        return (sd * (sd * x + 2 * cd * (cg * y - sg * z)) * x + cd**2 * (cg * y - sg * z)**2
                + (sg * y + cg * z)**2)

    def b(x, y, z):
        return (-sd * cd * (x**2 - (sg * z - cg * y)**2)
                + x * (sd**2 - cd**2) * (sg * z - cg * y))

    def c(x, y, z):
        return (cd * (cd * x + 2 * sd * (sg * z - cg * y)) * x + sd**2 * (cg * y - sg * z)**2
                + (sg * y + cg * z)**2)

    def d(x, y, z):
        return (-sd * (sg * cg * (z**2 - y**2) + y * z * (sg**2 - cg**2))
                + cd * (sg * y + cg * z) * x)

    def e(x, y, z):
        return (-cd * (sg * cg * (y**2 - z**2) + y * z * (cg**2 - sg**2))
                + sd * (sg * y + cg * z) * x)

    def f(x, y, z):
        return ((cd * x - sd * cg * y + sd * sg * z)**2
                + (sd * x + cd * cg * y - cd * sg * z)**2)

    ia, ib, ic, id_, ie, if_ = (_gauss_box_integral(fn, size, density)
                                for fn in (a, b, c, d, e, f))
    return np.array([[ia, ib, id_], [ib, ic, ie], [id_, ie, if_]])


def test_eq25_26_rotated_part_tensor(tmp_path, rng):
    for i in range(10):
        gamma, delta = rng.uniform(-np.pi, np.pi, 2)
        size, rho = rng.uniform(0.05, 0.6, 3), rng.uniform(500, 8000)
        folder = tmp_path / str(i)
        folder.mkdir()
        total = run_spec(folder, box_spec(size, rho, rpy=[gamma, 0.0, delta])).assembly.total
        assert_tensor(total.inertia, eq26_tensor(gamma, delta, size, rho), rtol=1e-11)


# --- eqs. 55-57 ----------------------------------------------------------------------

def quarter_cube_tensor(a, rho, axis):
    """Exact tensor about the cube's centre of the part of eq. 57, cube axes.

    The part is the quarter of the cube of side a on the positive side of the two axes
    normal to ``axis`` (for axis z: x, y in [0, a/2], z in [-a/2, a/2]). Every moment
    is rho a^5 / 24 (eq. 57); the one product in the cut plane is -rho a^5 / 64.
    """
    t = np.eye(3) * rho * a**5 / 24.0
    i, j = [k for k in range(3) if k != axis]
    t[i, j] = t[j, i] = -rho * a**5 / 64.0  # -rho * (integral x dx)(integral y dy) * a
    return t


@pytest.mark.parametrize("axis", [2, 1], ids=["about z (Figs. 9-10)", "about y (eq. 50)"])
@pytest.mark.parametrize("alpha", [0.0, 0.3, np.pi / 4, 1.0, 2.2, -0.7, np.pi])
def test_eq55_57_cube_part_in_rotated_frame(tmp_path, axis, alpha):
    # The element frame x'y'z' is turned by alpha about the axis (eq. 50 / Fig. 9); the part
    # (a box a/2 x a/2 x a) is described in that frame: its centre at A(-alpha) c and its
    # axes turned back by -alpha, so physically it is the cube's quarter. The tool must
    # compose the frames into B_z' = rho a^5 / 24 about the axis through the cube's centre,
    # in the rotated frame too, for every alpha.
    a, rho = 0.37, 2700.0
    rpy = np.zeros(3)
    rpy[axis] = alpha  # roll/pitch/yaw index = axis x/y/z
    c, size = np.full(3, a / 4.0), np.full(3, a / 2.0)
    c[axis], size[axis] = 0.0, a
    turn_back = np.eye(3)
    i, j = [k for k in range(3) if k != axis]
    ca, sa = np.cos(-alpha), np.sin(-alpha)
    turn_back[i, i], turn_back[i, j], turn_back[j, i], turn_back[j, j] = ca, -sa, sa, ca
    if axis == 1:  # a rotation about y runs z -> x: the sign of the 2-D angle flips
        turn_back = turn_back.T
    spec = box_spec(size, rho, element_rpy=rpy, xyz=turn_back @ c, rpy=-rpy)
    part = run_spec(tmp_path, spec).assembly.parts[0].mass_properties
    about_centre = part.about(np.zeros(3))
    assert about_centre[axis, axis] == pytest.approx(rho * a**5 / 24.0, rel=RTOL)
    assert_tensor(about_centre, quarter_cube_tensor(a, rho, axis))
    # the same moment read in the rotated (primed) frame
    back = turn_back.T  # primed axes in the cube frame
    primed = back.T @ about_centre @ back
    assert primed[axis, axis] == pytest.approx(rho * a**5 / 24.0, rel=RTOL)


# --- NM7MAR: eqs. 35, 43-49 ------------------------------------------------------------

#: The design of robots/README.md: L, alpha, beta, direction of the link, and per element
#: (name, a x b x h, r_c); density 2000 (link 1 pinned at 14.4 kg), 1800, 7850 (steel).
NM7MAR = {
    "link1": dict(L=0.44, alpha=0.08, beta=0.06, axis=0, rho=2000.0, elements=[
        ("r", (0.16, 0.15, 0.10), (0.0, 0.0, 0.01)),
        ("k", (None, 0.10, 0.08), (-0.01, 0.005, -0.02)),
        ("l", (0.10, 0.16, 0.15), (0.01, -0.005, 0.01))]),
    "link2": dict(L=0.35, alpha=0.06, beta=0.05, axis=0, rho=1800.0, elements=[
        ("r", (0.12, 0.12, 0.10), (0.0, 0.004, 0.0)),
        ("k", (None, 0.10, 0.06), (-0.005, -0.004, 0.01)),
        ("l", (0.09, 0.10, 0.16), (0.005, 0.0, -0.01))]),
    "link3": dict(L=0.24, alpha=0.025, beta=0.015, axis=2, rho=7850.0, elements=[
        ("r", (0.06, 0.06, 0.05), (0.003, 0.0, 0.0)),
        ("k", (0.03, 0.03, None), (0.0, 0.002, -0.005)),
        ("l", (0.09, 0.10, 0.02), (-0.003, -0.002, 0.005))]),
}


def nm7mar_elements(design):
    """(name, m, (a, b, h), 0_p in the link frame, r_c) with eq. 35 for k's length."""
    out = []
    for p, (name, dims, r_c) in enumerate(design["elements"]):
        dims = tuple(design["L"] - design["alpha"] - design["beta"] if d is None else d
                     for d in dims)  # eq. 35
        origin = np.zeros(3)
        origin[design["axis"]] = -design["L"] * p / 2.0  # 0_r, 0_k at L/2, 0_l at L (eq. 6)
        m = design["rho"] * np.prod(dims)
        out.append((name, m, dims, origin, np.array(r_c)))
    return out


def eq46(design):
    """Link CoM (eq. 3/12) and B tensor (eqs. 43-46) in the link frame."""
    elements = nm7mar_elements(design)
    masses = np.array([m for _, m, _, _, _ in elements])
    centres = np.array([o + r for _, _, _, o, r in elements])
    s = masses @ centres / masses.sum()  # eq. 3
    per_element = {}
    for name, m, (a, b, h), origin, r_c in elements:
        x, y, z = r_c + (origin - s)  # r_cp + r_op (eq. 41: 0_p seen from the link CoM)
        per_element[name] = np.array([  # eq. 43
            [m / 12 * (b**2 + h**2) + m * (y**2 + z**2), -m * x * y, -m * x * z],
            [-m * x * y, m / 12 * (a**2 + h**2) + m * (x**2 + z**2), -m * y * z],
            [-m * x * z, -m * y * z, m / 12 * (a**2 + b**2) + m * (x**2 + y**2)],
        ])
    return s, masses.sum(), per_element, sum(per_element.values())  # eq. 44


@pytest.fixture(scope="module")
def nm7mar_fixed(tmp_path_factory):
    options = FixOptions(spec=load_spec(ROOT / "robots" / "nm7mar.inertia.toml"))
    result = fix_file(ROOT / "robots" / "nm7mar.urdf", options)
    out = tmp_path_factory.mktemp("nm7mar") / "nm7mar.fixed.urdf"
    out.write_bytes(result.output)
    written, _ = read_urdf(out)
    return result, written


@pytest.mark.parametrize("link", sorted(NM7MAR))
def test_eq43_46_nm7mar_link_tensors(nm7mar_fixed, link):
    from urdfinertia.analysis.explain import link_breakdown

    result, written = nm7mar_fixed
    lr = next(r for r in result.links if r.name == link)
    s, mass, per_element, total = eq46(NM7MAR[link])
    assert lr.assembly.total.mass == pytest.approx(mass, rel=RTOL)
    np.testing.assert_allclose(lr.assembly.total.com, s, atol=1e-15)
    assert_tensor(lr.assembly.total.inertia, total)
    breakdown = link_breakdown(lr)
    for e in breakdown.elements:  # element by element, eq. 43
        assert_tensor(e.element.inertia_link, per_element[e.element.name])
    # and what was written into the URDF (printed with repr: full precision)
    inertial = written.link(link).inertial
    assert inertial.mass == pytest.approx(mass, rel=RTOL)
    assert_tensor(inertial.tensor_in_link(), total)


@pytest.mark.parametrize("link", sorted(NM7MAR))
def test_eq49_nm7mar_centre_of_mass(nm7mar_fixed, link):
    result, written = nm7mar_fixed
    design = NM7MAR[link]
    elements = nm7mar_elements(design)
    volumes = [np.prod(dims) for _, _, dims, _, _ in elements]
    np.testing.assert_allclose(volumes, volumes[0], rtol=1e-12)  # eq. 47 holds
    np.testing.assert_allclose(sum(r for *_, r in elements), 0.0, atol=1e-15)  # eq. 48
    expected = np.zeros(3)
    expected[design["axis"]] = -design["L"] / 2.0  # eq. 49
    np.testing.assert_allclose(written.link(link).inertial.origin.xyz, expected, atol=1e-12)


def test_nm7mar_spec_encodes_the_documented_design():
    # The shipped spec's element frames and part offsets are 0_p and r_cp of the design.
    spec = load_spec(ROOT / "robots" / "nm7mar.inertia.toml")
    for link, design in NM7MAR.items():
        ls = spec.link(link)
        for element, (name, _, dims, origin, r_c) in zip(ls.elements,
                                                         nm7mar_elements(design), strict=True):
            assert element.name == name
            np.testing.assert_allclose(element.origin.xyz, origin, atol=1e-15)
            (part,) = element.parts
            np.testing.assert_allclose(part.origin.xyz, r_c, atol=1e-15)
            np.testing.assert_allclose(part.source.size, dims, atol=1e-15)


@pytest.mark.parametrize("seed", range(8))
def test_eq49_holds_for_any_design_meeting_eqs47_48(tmp_path, seed):
    # Random cuboids of equal volume (eq. 47) with r_c summing to zero (eq. 48), one density:
    # the link's CoM must come out at L/2 along the link (eq. 49), whatever else varies.
    rng = np.random.default_rng(1000 + seed)
    axis = int(rng.integers(0, 3))
    length, rho, volume = rng.uniform(0.2, 1.5), rng.uniform(500, 9000), rng.uniform(1e-4, 1e-2)
    r_c = rng.uniform(-0.05, 0.05, (3, 3))
    r_c[2] = -r_c[0] - r_c[1]
    text = ""
    for p, name in enumerate("rkl"):
        sides = rng.uniform(0.5, 2.0, 3)
        sides *= (volume / np.prod(sides)) ** (1 / 3)
        origin = np.zeros(3)
        origin[axis] = -length * p / 2
        text += (f"[links.a.elements.{name}]\nxyz = {toml_vec(origin)}\n"
                 f"[links.a.elements.{name}.parts.box]\nbox = {{ size = {toml_vec(sides)} }}\n"
                 f"xyz = {toml_vec(r_c[p])}\ndensity = {rho!r}\n")
    com = run_spec(tmp_path, text).assembly.total.com
    expected = np.zeros(3)
    expected[axis] = -length / 2
    np.testing.assert_allclose(com, expected, atol=1e-12 * length)
