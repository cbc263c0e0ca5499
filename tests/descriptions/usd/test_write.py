"""usd/write.py: fix's override layer composes over the untouched asset; its MassAPI is
what fix computes for the source URDF; --in-place authors into the root layer."""

from __future__ import annotations

import hashlib
import subprocess
import sys

import numpy as np
import pytest
from descriptions.usd.assets import copy, source

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.usd.read import read, valid_identifier
from urdfinertia.descriptions.usd.write import override_path
from urdfinertia.plan.fix import fix_file

# float32 MassAPI values: mass and CoM to ~6e-8, the tensor through a float32 quaternion
# and diagonal to ~1e-7 of its largest moment; 1e-6 leaves a margin
F32 = 1e-6


def digest(folder):
    return {p: hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.rglob("*")
            if p.is_file()}


@pytest.mark.parametrize("name", ["double_pendulum", "cartpole", "spirit40"])
def test_override_composes_to_what_fix_computes_for_the_source(name, tmp_path):
    root = copy(name, tmp_path)
    before = digest(root.parent)
    options = FixOptions(recompute="all")
    fixed = fix_file(root, options)
    layer = override_path(root)
    layer.write_bytes(fixed.output)
    assert digest(root.parent) == {**before, layer: digest(root.parent)[layer]}
    composed = read(layer).robot
    from_urdf = fix_file(source(name), options)
    compared = 0
    for r in from_urdf.links:
        if r.assembly is None:
            continue
        want = r.assembly.total
        got = composed.link(valid_identifier(r.name)).inertial
        assert got is not None, r.name
        assert got.mass == pytest.approx(want.mass, rel=F32)
        np.testing.assert_allclose(got.origin.xyz, want.com, atol=F32)
        np.testing.assert_allclose(got.tensor_in_link(), want.inertia,
                                   atol=F32 * np.abs(want.inertia).max())
        compared += 1
    assert compared >= 3
    # Newton's full tensor is written beside the MassAPI and agrees with it
    assert not [f for f in composed.findings if f.code == "usd-newton-mass-disagrees"]


def test_override_layer_keeps_the_stage_units_and_default_prim(tmp_path):
    root = copy("cartpole", tmp_path)
    fixed = fix_file(root, FixOptions(recompute="all"))
    text = fixed.output.decode()
    assert f"@./{root.name}@" in text
    assert "metersPerUnit = 1" in text and "defaultPrim" in text
    assert "urdfinertia = {" in text  # the record of which prim each link is


def test_cli_writes_the_layer_elsewhere_with_its_sublayer_rewritten(tmp_path):
    root = copy("double_pendulum", tmp_path)
    out = tmp_path / "elsewhere" / "fixed.usda"
    out.parent.mkdir()
    done = subprocess.run([sys.executable, "-m", "urdfinertia", "fix", "-q", "--all",
                           str(root), "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert f"@../double_pendulum/{root.name}@" in out.read_text()
    robot, _ = read_description(out)
    assert len(robot.links) == 3


def test_in_place_authors_into_the_root_layer(tmp_path):
    from urdfinertia.descriptions.usd.write import in_place

    root = copy("spirit40", tmp_path)
    payload = root.parent / "Payload" / "Physics.usda"
    payload_before = payload.read_bytes()
    fixed = fix_file(root, FixOptions(recompute="all"))
    in_place(root, fixed.output)
    assert payload.read_bytes() == payload_before  # only the root layer changes
    assert root.with_name(root.name + ".bak").is_file()
    after = read(root).robot
    for r in fixed.links:
        if r.assembly is not None:
            got = after.link(r.name).inertial
            assert got is not None
            assert got.mass == pytest.approx(r.assembly.total.mass, rel=F32)


def test_cli_fix_writes_the_override_layer_beside_the_asset_by_default(tmp_path):
    root = copy("cartpole", tmp_path)
    before = digest(root.parent)
    done = subprocess.run([sys.executable, "-m", "urdfinertia", "fix", "-q", "--all",
                           str(root)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    layer = override_path(root)
    assert layer.name == "physics.inertia.usda"
    assert done.stdout == ""  # written to the layer, not printed
    after = digest(root.parent)
    assert {p: h for p, h in after.items() if p != layer} == before
    assert "over " in layer.read_text()


def test_cli_fix_in_place_changes_only_the_root_layer(tmp_path):
    root = copy("cartpole", tmp_path)
    original = root.read_bytes()
    before = digest(root.parent)
    done = subprocess.run([sys.executable, "-m", "urdfinertia", "fix", "-q", "--all",
                           "--in-place", str(root)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    after = digest(root.parent)
    changed = {p for p in after if after[p] != before.get(p)}
    assert changed == {root, root.with_name(root.name + ".bak")}
    assert root.with_name(root.name + ".bak").read_bytes() == original
    assert not override_path(root).exists()
    text = root.read_text()
    assert "physics:mass" in text and "urdfinertia = {" not in text
