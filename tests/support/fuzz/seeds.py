"""The real files the fuzzer mutates, found in the installed collections.

A description seed is a file and what its references need: ``package_dirs`` for
``package://`` and ``model://`` names, or a ``root`` folder that the case mirrors (a tree
of symbolic links to the real entries) so that the mutant, written beside the original in
the mirror, resolves its relative references (MJCF includes and meshes, USD sublayers and
payloads, SDFormat URIs) as the original does. The originals are only ever read.

A mesh seed is a real mesh file's bytes; PLY, GLB and ASCII STL seeds are made from a real
binary STL with trimesh's exporters (no collection ships those formats).
"""

from __future__ import annotations

import functools
import importlib.util
from dataclasses import dataclass
from pathlib import Path

from support.corpus import example_robot_data_dir

#: Description formats, in table order.
DESCRIPTION_FORMATS = ("urdf", "xacro", "sdf", "mjcf", "usd")
#: Mesh formats, in table order.
MESH_FORMATS = ("stl", "stl-ascii", "obj", "dae", "ply", "glb")

_REPO = Path(__file__).resolve().parents[3]


@dataclass(frozen=True)
class DescriptionSeed:
    """A real description file to mutate.

    name : short id ("erd/panda").
    fmt : one of :data:`DESCRIPTION_FORMATS`.
    path : the file.
    root : folder to mirror so relative references resolve (None: the mutant may live
        anywhere: its references are ``package://`` names or absent).
    package_dirs : ``--package-dir`` pairs the references need.
    """

    name: str
    fmt: str
    path: Path
    root: Path | None = None
    package_dirs: tuple[tuple[str, Path], ...] = ()

    @property
    def suffix(self) -> str:
        """The file name's suffixes as the format is recognised (".urdf.xacro")."""
        name = self.path.name
        return name[name.index("."):] if "." in name else ""

    @property
    def output_suffix(self) -> str:
        return {"xacro": ".urdf", "usd": ".usda"}.get(self.fmt, self.path.suffix)


@dataclass(frozen=True)
class MeshSeed:
    """A real mesh (or one made from a real mesh) to mutate: ``fmt`` in :data:`MESH_FORMATS`."""

    name: str
    fmt: str
    source: Path

    @property
    def suffix(self) -> str:
        return {"stl-ascii": ".stl"}.get(self.fmt, f".{self.fmt}")

    def data(self) -> bytes:
        return mesh_seed_bytes(self.fmt, str(self.source))


def _package_root(module: str) -> Path | None:
    spec = importlib.util.find_spec(module)  # finds the folder, runs nothing
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(next(iter(spec.submodule_search_locations)))


#: (name, format, path below the example-robot-data ``robots`` folder)
_ERD = (
    ("erd/double_pendulum", "urdf", "double_pendulum_description/urdf/double_pendulum.urdf"),
    ("erd/allegro", "urdf", "allegro_hand_description/urdf/allegro_right_hand.urdf"),
    ("erd/panda", "urdf", "panda_description/urdf/panda.urdf"),
    ("erd/ur5", "urdf", "ur_description/urdf/ur5_robot.urdf"),
    ("erd/simple_humanoid", "urdf", "simple_humanoid_description/urdf/simple_humanoid.urdf"),
    ("erd/solo12", "urdf", "solo_description/robots/solo12.urdf"),
    ("erd/hector", "urdf", "hector_description/robots/quadrotor_base.urdf"),
    ("erd/hector", "xacro", "hector_description/robots/quadrotor_base.urdf.xacro"),
    ("erd/cassie", "sdf", "cassie_description/robots/cassie_simple.sdf"),
)
#: (name, format, collection module, path inside it, folder to mirror inside it)
_INSTALLED = (
    ("drake/acrobot", "sdf", "pydrake", "share/drake/examples/acrobot/Acrobot.sdf", None),
    ("drake/cart_pole", "sdf", "pydrake",
     "share/drake/examples/multibody/cart_pole/cart_pole.sdf", None),
    ("drake/planar_gripper", "sdf", "pydrake",
     "share/drake/examples/planar_gripper/planar_gripper.sdf", None),
    ("pybullet/kuka_iiwa", "sdf", "pybullet_data", "kuka_iiwa/model.sdf", "kuka_iiwa"),
    ("dm_control/cartpole", "mjcf", "dm_control", "suite/cartpole.xml", "suite"),
    ("dm_control/acrobot", "mjcf", "dm_control", "suite/acrobot.xml", "suite"),
    ("dm_control/hopper", "mjcf", "dm_control", "suite/hopper.xml", "suite"),
    ("dm_control/finger", "mjcf", "dm_control", "suite/finger.xml", "suite"),
    ("robosuite/panda", "mjcf", "robosuite", "models/assets/robots/panda/robot.xml",
     "models/assets/robots/panda"),
)
#: (name, format, path below tests/data, folder to mirror below tests/data)
_REPO_DATA = (
    ("inline/base", "urdf", "fuzz/base.urdf", "fuzz"),
    ("xacro/rover", "xacro", "xacro/nested/rover.urdf.xacro", "xacro/nested"),
    ("xacro/humanoid", "xacro", "xacro/limbs/humanoid.urdf.xacro", "xacro/limbs"),
    ("xacro/fr3", "xacro", "xacro/franka_description/robots/fr3/fr3.urdf.xacro",
     "xacro/franka_description"),
    ("usd/bad_mass", "usd", "usd/handmade/bad_mass.usda", "usd/handmade"),
    ("usd/double_pendulum", "usd", "usd/double_pendulum/2dof_planar.usda",
     "usd/double_pendulum"),
    ("usd/cartpole", "usd", "usd/cartpole/physics.usda", "usd/cartpole"),
)


@functools.lru_cache(maxsize=1)
def description_seeds() -> tuple[DescriptionSeed, ...]:
    """Every description seed whose file is installed here, in a fixed order."""
    out: list[DescriptionSeed] = []
    erd = example_robot_data_dir()
    if erd is not None:
        dirs = (("example-robot-data", erd),)
        for name, fmt, rel in _ERD:
            path = erd / "robots" / rel
            if path.is_file():
                out.append(DescriptionSeed(name, fmt, path, package_dirs=dirs))
    for name, fmt, module, rel, mirror in _INSTALLED:
        base = _package_root(module)
        if base is not None and (base / rel).is_file():
            out.append(DescriptionSeed(name, fmt, base / rel,
                                       root=base / mirror if mirror else None))
    data = _REPO / "tests" / "data"
    for name, fmt, rel, mirror in _REPO_DATA:
        if (data / rel).is_file():
            out.append(DescriptionSeed(name, fmt, data / rel, root=data / mirror))
    return tuple(out)


#: (name, format, path below the example-robot-data ``robots`` folder)
_ERD_MESHES = (
    ("panda/link3", "stl", "panda_description/meshes/collision/link3.stl"),
    ("allegro/link_1", "stl", "allegro_hand_description/meshes/link_1.0.STL"),
    ("cassie/foot", "stl", "cassie_description/meshes/foot.stl"),
    ("humanoid/box", "stl-ascii", "simple_humanoid_description/meshes/box.stl"),
    ("panda/link1", "stl-ascii", "panda_description/meshes/collision/link1.stl"),
    ("alexander/foot", "obj", "alexander_description/meshes/Foot.obj"),
    ("solo/cube", "obj", "solo_description/meshes/cube.obj"),
    ("anymal_c/foot", "dae", "anymal_c_simple_description/meshes/foot.dae"),
    ("hyq/lowerleg", "dae", "hyq_description/meshes/leg/lowerleg.dae"),
    ("panda/finger", "dae", "panda_description/meshes/visual/finger.dae"),
    ("panda/link4", "ply", "panda_description/meshes/collision/link4.stl"),
    ("allegro/link_2", "ply", "allegro_hand_description/meshes/link_2.0.STL"),
    ("panda/link5", "glb", "panda_description/meshes/collision/link5.stl"),
    ("cassie/knee", "glb", "cassie_description/meshes/knee.stl"),
)


@functools.lru_cache(maxsize=1)
def mesh_seeds() -> tuple[MeshSeed, ...]:
    """Every mesh seed whose source is installed here, in a fixed order."""
    erd = example_robot_data_dir()
    if erd is None:
        return ()
    return tuple(MeshSeed(name, fmt, erd / "robots" / rel) for name, fmt, rel in _ERD_MESHES
                 if (erd / "robots" / rel).is_file())


@functools.lru_cache(maxsize=64)
def mesh_seed_bytes(fmt: str, source: str) -> bytes:
    """The seed file's bytes in format ``fmt``: the file itself for its own format, else
    exported by trimesh (ASCII STL, PLY binary, GLB) from the file's triangles."""
    data = Path(source).read_bytes()
    own = {"stl": ".stl", "obj": ".obj", "dae": ".dae"}
    if own.get(fmt) == Path(source).suffix.lower():
        return data
    import io

    import trimesh

    mesh = trimesh.load(io.BytesIO(data), file_type=Path(source).suffix.lower()[1:],
                        force="mesh", process=False)
    if fmt == "stl-ascii":
        return trimesh.exchange.stl.export_stl_ascii(mesh).encode()
    if fmt == "ply":
        return trimesh.exchange.ply.export_ply(mesh, encoding="binary", include_attributes=False)
    if fmt == "glb":
        return trimesh.exchange.gltf.export_glb(trimesh.Scene(mesh), include_normals=False)
    raise ValueError(f"no seed conversion to {fmt} from {source}")
