"""The public API of ``urdfinertia/__init__.py``: light to import, complete, working."""

import subprocess
import sys

import pytest

import urdfinertia


def test_importing_the_package_loads_no_heavy_library():
    code = ("import sys, urdfinertia\n"
            "heavy = {'lxml', 'trimesh', 'numpy', 'scipy', 'collada', 'rich'}\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_every_name_resolves_to_its_module():
    for name in urdfinertia.__all__:
        value = getattr(urdfinertia, name)
        assert value.__name__ == name
        assert value.__module__ == urdfinertia._API[name]


def test_unknown_name_raises_attribute_error():
    try:
        urdfinertia.no_such_thing  # noqa: B018
    except AttributeError as exc:
        assert "no_such_thing" in str(exc)
    else:
        raise AssertionError("no AttributeError")


def test_fix_file_through_the_public_api(robots_dir):
    options = urdfinertia.FixOptions(spec=urdfinertia.load_spec(robots_dir / "nm7mar.inertia.toml"))
    result = urdfinertia.fix_file(robots_dir / "nm7mar.urdf", options)
    assert result.changed
    totals = {r.name: r.assembly.total for r in result.links if r.assembly is not None}
    assert set(totals) >= {"link1", "link2", "link3"}
    assert all(isinstance(t, urdfinertia.MassProperties) and t.is_physical()
               for t in totals.values())


def test_an_unknown_option_names_itself_and_the_known_ones(robots_dir):
    with pytest.raises(TypeError) as caught:
        urdfinertia.fix(robots_dir / "nm7mar.urdf", output="out.urdf")
    message = str(caught.value)
    assert "'output'" in message and "result.save(path)" in message
    assert "density" in message and "geometry" in message
    with pytest.raises(TypeError, match="unknown options 'colour', 'size'"):
        urdfinertia.fix(robots_dir / "nm7mar.urdf", colour=1, size=2)
