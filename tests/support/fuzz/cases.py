"""Fuzz cases: drawn from a seed, made on disk, and the commands run on each.

Case ``i`` of generator seed ``S`` is drawn from its own ``random.Random(f"{S}:{i}")``, so
one case can be made again without the others (``scripts/fuzz.py --case I``) and a run of
N cases is a prefix of a run of N + 1.
"""

from __future__ import annotations

import hashlib
import os
import random
from dataclasses import dataclass
from pathlib import Path

from support.fuzz.meshes import mutate_mesh
from support.fuzz.mutate import CASE_MARK, Edit, Fixture, mutate
from support.fuzz.seeds import (
    DESCRIPTION_FORMATS,
    MESH_FORMATS,
    DescriptionSeed,
    description_seeds,
    mesh_seeds,
)

#: Share of description cases (the rest mutate a mesh under a small URDF).
DESCRIPTION_SHARE = 0.7
#: The commands run on every case, by name ("fix-strict", ``fix --strict``, on request).
COMMANDS = ("check", "fix", "fix-all")


@dataclass(frozen=True)
class Case:
    """One mutant.

    group : "description" or "mesh".
    fmt : the mutated file's format (a description or a mesh format).
    seed : the seed's name.
    kinds : the mutations, in the order applied.
    data : the mutated file (with ``@CASE@`` markers for the case folder).
    fixtures : file-system objects the mutant refers to.
    """

    index: int
    group: str
    fmt: str
    seed: str
    kinds: tuple[str, ...]
    data: bytes
    fixtures: tuple[Fixture, ...] = ()

    @property
    def label(self) -> str:
        return f"#{self.index} {self.fmt} {self.seed} [{'+'.join(self.kinds)}]"


def make_case(generator_seed: int, index: int, formats: tuple[str, ...] | None = None,
              ) -> Case:
    """Case ``index`` of ``generator_seed`` (``formats``: only these formats)."""
    rng = random.Random(f"{generator_seed}:{index}")
    described = [s for s in description_seeds() if formats is None or s.fmt in formats]
    meshes = [s for s in mesh_seeds() if formats is None or s.fmt in formats]
    if not described and not meshes:
        raise ValueError(f"no seed of the formats {formats} is installed")
    if meshes and (not described or rng.random() >= DESCRIPTION_SHARE):
        fmts = [f for f in MESH_FORMATS if any(s.fmt == f for s in meshes)]
        fmt = rng.choice(fmts)
        seed = rng.choice([s for s in meshes if s.fmt == fmt])
        data = seed.data()
        kinds = []
        # a geometric mutation needs a readable file: it comes first, bytes after it
        for _ in range(rng.choice((1, 1, 1, 2))):
            kind, data = mutate_mesh(data, fmt, rng) if not kinds else _after(data, fmt, rng)
            kinds.append(kind)
        return Case(index, "mesh", fmt, seed.name, tuple(kinds), data)
    fmts = [f for f in DESCRIPTION_FORMATS if any(s.fmt == f for s in described)]
    fmt = rng.choice(fmts)
    dseed = rng.choice([s for s in described if s.fmt == fmt])
    data = dseed.path.read_bytes()
    edits: list[Edit] = []
    for _ in range(rng.choice((1, 1, 1, 2, 3))):
        edit = mutate(data, fmt, rng)
        edits.append(edit)
        data = edit.data
    fixtures = tuple(f for e in edits for f in e.fixtures)
    return Case(index, "description", fmt, dseed.name, tuple(e.kind for e in edits), data,
                fixtures)


def _after(data: bytes, fmt: str, rng: random.Random) -> tuple[str, bytes]:
    from support.fuzz import meshes

    for _ in range(4):
        group = rng.choice((meshes._SPECIFIC[fmt][0], meshes._bytes))
        try:
            return group(data, fmt, rng)
        except Exception:  # a mutant the format parsers of the mutator cannot read
            continue
    return meshes._bytes(data, fmt, rng)


def make_cases(generator_seed: int, count: int, formats: tuple[str, ...] | None = None,
               start: int = 0) -> list[Case]:
    return [make_case(generator_seed, i, formats) for i in range(start, start + count)]


def seed_by_name(name: str, fmt: str) -> DescriptionSeed:
    for s in description_seeds():
        if s.name == name and s.fmt == fmt:
            return s
    raise KeyError((name, fmt))


# --- on disk -------------------------------------------------------------------------

@dataclass(frozen=True)
class Made:
    """A case on disk: the file the commands read, its folder, where outputs go, and the
    options every command gets."""

    input: Path
    folder: Path  # the case's own folder (fixtures, the mutant or the mirror)
    out: Path
    options: tuple[str, ...]
    output_suffix: str


MESH_URDF = """<?xml version="1.0"?>
<robot name="fuzz_mesh">
  <link name="base">
    <inertial><mass value="2"/>
      <inertia ixx="0.0083" ixy="0" ixz="0" iyy="0.0083" iyz="0" izz="0.0133"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <link name="part">
    <inertial><origin xyz="0 0 0.01" rpy="0 0 0"/><mass value="0.5"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <visual><geometry><mesh filename="{mesh}"/></geometry></visual>
    <collision><geometry><mesh filename="{mesh}"/></geometry></collision>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="part"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""


def materialize(case: Case, folder: Path) -> Made:
    """Write ``case`` under ``folder`` (which must not exist)."""
    folder.mkdir(parents=True)
    inputs = folder / "in"
    inputs.mkdir()
    out = folder / "out"
    out.mkdir()
    if case.group == "mesh":
        suffix = {"stl-ascii": ".stl"}.get(case.fmt, f".{case.fmt}")
        (inputs / f"mesh{suffix}").write_bytes(case.data)
        robot = inputs / "robot.urdf"
        robot.write_text(MESH_URDF.format(mesh=f"mesh{suffix}"))
        return Made(robot, inputs, out, (), ".urdf")
    seed = seed_by_name(case.seed, case.fmt)
    if seed.root is not None:
        rel = seed.path.relative_to(seed.root)
        top = inputs / seed.root.name
        mirror(seed.root, top, rel.parent)
        target = top / rel.parent / f"fuzz{case.index}_{seed.path.name}"
    else:
        target = inputs / f"fuzz{case.index}_{seed.path.name}"
    data = case.data.replace(CASE_MARK + b"/SELF", os.fsencode(target))
    data = data.replace(CASE_MARK, os.fsencode(inputs))
    target.write_bytes(data)
    for fixture in case.fixtures:
        make_fixture(inputs, fixture)
    options = tuple(f"--package-dir={name}={path}" for name, path in seed.package_dirs)
    return Made(target, inputs, out, options, seed.output_suffix)


def mirror(source: Path, top: Path, down: Path) -> None:
    """``top`` as a tree of symbolic links to ``source``'s entries, with real folders on
    the way ``down`` to the folder the mutant is written in."""
    here, there = top, source
    here.mkdir(parents=True, exist_ok=True)
    parts = list(down.parts)
    while True:
        nxt = parts.pop(0) if parts else None
        for entry in sorted(os.listdir(there)):
            if entry != nxt:
                os.symlink(there / entry, here / entry)
        if nxt is None:
            return
        here, there = here / nxt, there / nxt
        here.mkdir()


def make_fixture(folder: Path, fixture: Fixture) -> None:
    path = folder / fixture.name
    if path.exists() or path.is_symlink():
        return
    if fixture.kind == "fifo":
        os.mkfifo(path)
    elif fixture.kind == "dir":
        path.mkdir()
    elif fixture.kind == "sparse":
        with open(path, "wb") as fh:
            fh.truncate(fixture.size)
    elif fixture.kind == "loop":
        os.symlink(path.with_name(path.name + ".2"), path)
        os.symlink(path, path.with_name(path.name + ".2"))
    elif fixture.kind == "link":
        os.symlink(fixture.target, path)
    elif fixture.kind == "empty":
        path.write_bytes(b"")
    else:
        path.write_bytes(fixture.data)


def commands(made: Made) -> dict[str, list[str]]:
    """argv of each of :data:`COMMANDS` for the case on disk."""
    out = made.out
    base = [str(made.input), *made.options]
    return {
        "check": ["check", *base, "-q"],
        "fix": ["fix", *base, "-o", str(out / f"fix{made.output_suffix}"),
                "--json", str(out / "fix.json"), "-q"],
        "fix-all": ["fix", *base, "--all", "-o", str(out / f"fix-all{made.output_suffix}"),
                    "--json", str(out / "fix-all.json"), "-q"],
        "fix-strict": ["fix", *base, "--strict", "-o",
                       str(out / f"fix-strict{made.output_suffix}"),
                       "--json", str(out / "fix-strict.json"), "-q"],
    }


def snapshot(folder: Path) -> dict[str, str]:
    """Every entry below ``folder`` (not following symbolic links) with its kind, and a
    regular file's digest: what a run must leave as it found it."""
    found: dict[str, str] = {}
    for root, dirs, files in os.walk(folder, followlinks=False):
        for name in dirs + files:
            path = Path(root) / name
            rel = str(path.relative_to(folder))
            if path.is_symlink():
                found[rel] = "link:" + os.readlink(path)
            elif path.is_dir():
                found[rel] = "dir"
            elif path.is_file():
                info = path.stat()
                if info.st_blocks * 512 < info.st_size // 2:  # sparse: size only
                    found[rel] = f"sparse:{info.st_size}"
                else:
                    found[rel] = hashlib.sha1(path.read_bytes()).hexdigest()
            else:
                found[rel] = "special"
    return found
