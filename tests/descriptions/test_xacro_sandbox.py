"""descriptions/xacro: the sandbox around what xacro reads and evaluates. Each case was
found by a hostile-input review: it copied a local file into the output (exit 0), hung,
or failed without a line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from support.xacro_files import HEAD, clean_xacro_settings, write  # noqa: F401 - the fixture

from urdfinertia.cli import main
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.xacro.expand import configure
from urdfinertia.errors import UrdfError


def yaml_robot(folder: Path, yaml_path: str) -> Path:
    return write(folder, "robot/r.urdf.xacro", HEAD
                 + f'  <xacro:property name="p" value="${{xacro.load_yaml(\'{yaml_path}\')}}"/>\n'
                 + '  <link name="${p}"/>\n</robot>\n')


@pytest.mark.parametrize("outside", ["/etc/passwd", "../secret.yaml"])
def test_load_yaml_outside_the_robot_is_refused_with_its_line(tmp_path, outside, capsys):
    write(tmp_path, "secret.yaml", "token-1234\n")
    path = yaml_robot(tmp_path, outside)
    with pytest.raises(UrdfError, match="reads only files under the robot's folder") as exc:
        read_description(path)
    assert exc.value.file == str(path) and exc.value.line in (3, 4)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}:" in err and "token-1234" not in err and "root:" not in err


def test_includes_outside_the_robot_are_refused(tmp_path):
    write(tmp_path, "other/evil.xacro", HEAD + '  <link name="a"/>\n</robot>\n')
    path = write(tmp_path, "robot/r.urdf.xacro",
                 HEAD + '  <xacro:include filename="../other/evil.xacro"/>\n</robot>\n')
    with pytest.raises(UrdfError, match="reads only files under") as exc:
        read_description(path)
    assert exc.value.file == str(path) and exc.value.line == 3


def test_files_of_the_package_and_package_dirs_are_read(tmp_path):
    """The main file's folder tree, its package (a package.xml above) and --package-dir."""
    write(tmp_path, "pkg/package.xml", "<package><name>pkg</name></package>\n")
    write(tmp_path, "pkg/config/p.yaml", "name: base\n")
    write(tmp_path, "lib/l.yaml", "name: arm\n")
    path = write(tmp_path, "pkg/urdf/r.urdf.xacro", HEAD
                 + '  <xacro:property name="p"'
                 + ' value="${xacro.load_yaml(\'../config/p.yaml\')}"/>\n'
                 + '  <xacro:property name="q"'
                 + ' value="${xacro.load_yaml(\'$(find lib)/l.yaml\')}"/>\n'
                 + '  <link name="${p[\'name\']}"/>\n  <link name="${q[\'name\']}"/>\n'
                 + '  <joint name="j" type="fixed"><parent link="base"/><child link="arm"/>'
                 + "</joint>\n</robot>\n")
    configure(package_dirs={"lib": tmp_path / "lib"})
    robot = read_description(path)[0]
    assert [link.name for link in robot.links] == ["base", "arm"]


def run_with_timeout(argv: list[str]) -> subprocess.CompletedProcess:
    """The CLI in a subprocess: a FIFO opened for reading would block it forever."""
    return subprocess.run([sys.executable, "-m", "urdfinertia", *argv], capture_output=True,
                          text=True, timeout=60)


@pytest.mark.parametrize("how", ["include", "load_yaml"])
def test_a_fifo_is_refused_without_blocking(tmp_path, how):
    os.mkfifo(tmp_path / "pipe.xacro")
    body = ('  <xacro:include filename="pipe.xacro"/>\n' if how == "include" else
            '  <xacro:property name="p" value="${xacro.load_yaml(\'pipe.xacro\')}"/>\n'
            '  <link name="${p}"/>\n')
    path = write(tmp_path, "r.urdf.xacro", HEAD + body + "</robot>\n")
    done = run_with_timeout(["check", str(path)])
    assert done.returncode == 2
    assert "reads only regular files" in done.stderr and f"{path}:" in done.stderr


@pytest.mark.parametrize(("expression", "shown"), [
    ("10**(10**8)", "10 ** 100000000"), ("2**n", "2 ** 100000000"),
    ("1 &lt;&lt; n", "1 << 100000000"),
])
def test_huge_integers_are_refused_not_computed(tmp_path, expression, shown):
    path = write(tmp_path, "r.urdf.xacro", HEAD
                 + '  <xacro:property name="n" value="100000000"/>\n'
                 + f'  <link name="a${{{expression}}}"/>\n</robot>\n')
    done = run_with_timeout(["check", str(path)])
    assert done.returncode == 2
    assert shown in done.stderr and f"{path}:4" in done.stderr


def test_ordinary_powers_still_evaluate(tmp_path):
    path = write(tmp_path, "r.urdf.xacro", HEAD
                 + '  <link name="a${2**10}_${int(0.5**-2)}_${1 &lt;&lt; 3}_${10**-3}"/>\n'
                 + "</robot>\n")
    assert read_description(path)[0].links[0].name == "a1024_4_8_0.001"


def test_deep_macro_recursion_names_its_line(tmp_path):
    path = write(tmp_path, "r.urdf.xacro", HEAD
                 + '  <xacro:macro name="m" params="n"><xacro:if value="${n > 0}">'
                 + '<xacro:m n="${n-1}"/></xacro:if></xacro:macro>\n'
                 + '  <xacro:m n="300"/>\n</robot>\n')
    with pytest.raises(UrdfError, match="recursion too deep") as exc:
        read_description(path)
    assert exc.value.file == str(path) and exc.value.line in (3, 4)


def test_a_huge_include_name_is_refused_at_once(tmp_path):
    """Fuzz (seed 5): a megabyte of letters as an include's name hung the scheme search
    (quadratic); a name longer than PATH_MAX is refused with its line."""
    path = write(tmp_path, "r.urdf.xacro", HEAD + f'  <xacro:include filename="{"A" * 5000}"/>\n'
                 '  <link name="a"/>\n</robot>\n')
    with pytest.raises(UrdfError, match="more than 4096"):
        read_description(path)
