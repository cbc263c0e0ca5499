"""usd/stage.py: a corrupt, truncated or incomplete asset is one line naming the layer,
exit 2, and nothing written; a missing pxr says how to install it."""

from __future__ import annotations

import shutil
import subprocess
import sys

import pytest
from descriptions.usd.assets import DATA

from urdfinertia.errors import UrdfError


def run(*args):
    return subprocess.run([sys.executable, "-m", "urdfinertia", *map(str, args)],
                          capture_output=True, text=True)


@pytest.mark.parametrize(("name", "data", "cause"), [
    ("corrupt.usda", b"#usda 1.0\n(\n  garbage = \n", "corrupt.usda:3:"),
    ("noise.usdc", bytes(range(256)) * 2, "USD cannot read this layer"),
    ("truncated.usdc", b"PXR-USDC\0\0\0\0", "USD cannot read this layer"),
])
def test_unreadable_layer_is_one_line_exit_2_and_nothing_written(tmp_path, name, data,
                                                                   cause):
    bad = tmp_path / name
    bad.write_bytes(data)
    out = tmp_path / "out.usda"
    done = run("fix", bad, "-o", out)
    assert done.returncode == 2
    lines = [ln for ln in done.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith(f"urdf-inertia: error: {bad}: ")
    assert cause in lines[0]
    assert not out.exists()
    assert bad.read_bytes() == data


def test_missing_payload_layer_is_named(tmp_path):
    asset = tmp_path / "cartpole"
    shutil.copytree(DATA / "cartpole", asset)
    (asset / "Payload" / "Physics.usda").unlink()
    root = asset / "physics.usda"
    out = tmp_path / "out.usda"
    fixed = run("fix", root, "-o", out)
    assert fixed.returncode == 2
    assert "layer ./Physics.usda (named in Payload/Contents.usda) cannot be opened" in \
        fixed.stderr
    assert "Warning" not in fixed.stderr  # USD's own diagnostics are not printed
    assert not out.exists()
    checked = run("check", root)
    assert "missing-layer" in checked.stdout + checked.stderr
    assert checked.returncode != 0


def test_missing_pxr_names_the_install_command(monkeypatch):
    from urdfinertia.descriptions.usd import stage

    monkeypatch.setitem(sys.modules, "pxr", None)  # import pxr -> ImportError
    with pytest.raises(UrdfError, match="pip install usd-core"):
        stage.pxr()


def test_not_a_usd_suffix_is_refused(tmp_path):
    from urdfinertia.descriptions.usd.stage import open_stage

    other = tmp_path / "robot.obj"
    other.write_text("v 0 0 0\n")
    with pytest.raises(UrdfError, match="not a USD file"):
        open_stage(other)


ROOT_WITH_SUBLAYER = '#usda 1.0\n(\n    subLayers = [@{}@]\n)\n\ndef Xform "robot" {{}}\n'


@pytest.mark.parametrize("kind", ["fifo", "device", "folder"])
def test_a_sublayer_that_is_not_a_regular_file_is_refused_before_usd_reads_it(tmp_path,
                                                                             kind):
    """USD blocks for ever opening a FIFO and reads a device to its end: every layer the
    stage composes is checked first (found by fuzzing: a reference to a FIFO hung)."""
    import os

    target = {"fifo": tmp_path / "pipe.usda", "device": "/dev/zero",
              "folder": tmp_path / "folder.usda"}[kind]
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "folder":
        target.mkdir()
    root = tmp_path / "robot.usda"
    root.write_text(ROOT_WITH_SUBLAYER.format(target))
    for argv in (["check", root], ["fix", root, "-o", tmp_path / "out.usda"]):
        done = subprocess.run([sys.executable, "-m", "urdfinertia", *map(str, argv)],
                              capture_output=True, text=True, timeout=60)
        assert done.returncode == 2, done.stderr
        assert "is not a regular file" in done.stderr and str(target) in done.stderr
        assert "internal error" not in done.stderr
    assert not (tmp_path / "out.usda").exists()


def test_a_sublayer_usd_cannot_parse_is_a_missing_layer_not_a_crash(tmp_path):
    """An empty file named as a sublayer: USD raises while the missing layers are listed
    (found by fuzzing: ``ErrorException ... is not a valid usda layer``, exit 3)."""
    (tmp_path / "empty.usda").write_bytes(b"")
    root = tmp_path / "robot.usda"
    root.write_text(ROOT_WITH_SUBLAYER.format("./empty.usda"))
    checked = run("check", root)
    assert checked.returncode == 1, checked.stderr
    assert "missing-layer" in checked.stdout and "internal error" not in checked.stderr
    fixed = run("fix", root, "-o", tmp_path / "out.usda")
    assert fixed.returncode == 2 and "empty.usda" in fixed.stderr, fixed.stderr
    assert "internal error" not in fixed.stderr


def test_an_error_quoting_bytes_that_are_not_utf8_is_one_line(tmp_path):
    """pxr's message quotes the layer's bytes; converting it raised UnicodeDecodeError
    (found by fuzzing: one flipped byte in a usda layer, exit 3)."""
    bad = tmp_path / "robot.usda"
    bad.write_bytes(b'#usda 1.0\n\ndef Xform "robot" {\n    double \x98x = 1\n}\n')
    done = run("check", bad)
    assert done.returncode == 2, done.stderr
    assert done.stderr.startswith(f"urdf-inertia: error: {bad}: ")
    assert "internal error" not in done.stderr
