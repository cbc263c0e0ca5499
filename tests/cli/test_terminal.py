"""What ``fix`` prints: at 80 and 200 columns on a terminal, and plain text when piped.

A terminal is simulated with rich's ``TTY_COMPATIBLE=1`` and its width with ``COLUMNS``;
without them, pytest's captured streams are what a pipe is. Widths are measured on the
visible text (ANSI codes stripped).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from urdfinertia.cli import main
from urdfinertia.plan.results import LinkResult
from urdfinertia.render.table import _notes

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from support.corpus import example_robot_data_dir  # noqa: E402

_ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")
_BOX_DRAWING = re.compile("[\u2500-\u257f]")


@pytest.fixture
def panda() -> Path:
    root = example_robot_data_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    return root / "robots" / "panda_description" / "urdf" / "panda.urdf"


def run_fix(path: Path, tmp_path: Path, capsys) -> list[str]:  # noqa: ANN001
    assert main(["fix", str(path), "-o", str(tmp_path / "out.urdf")]) == 0
    out = capsys.readouterr().out  # with -o the table is the command's output
    return [_ANSI.sub("", line) for line in out.splitlines()]


@pytest.mark.parametrize(("columns", "width"), [(None, 100), ("80", 80), ("200", 200)])
def test_piped_output_is_plain_text_that_fits(panda, tmp_path, capsys, monkeypatch,
                                              columns, width):
    monkeypatch.delenv("TTY_COMPATIBLE", raising=False)
    monkeypatch.delenv("FORCE_COLOR", raising=False)
    if columns is None:
        monkeypatch.delenv("COLUMNS", raising=False)
    else:
        monkeypatch.setenv("COLUMNS", columns)
    lines = run_fix(panda, tmp_path, capsys)
    assert len(lines) > 15
    assert max(map(len, lines)) <= width
    assert max(map(len, lines)) >= width - 2  # the table uses the width it is given
    text = "\n".join(lines)
    assert not _BOX_DRAWING.search(text) and "\x1b" not in text
    assert "panda_link1" in text and re.search(r"±\d+", text)
    assert "of CAD" not in text  # the long form is for --json and explain


@pytest.mark.parametrize("columns", [80, 200])
def test_terminal_output_fits_its_width(panda, tmp_path, capsys, monkeypatch, columns):
    monkeypatch.setenv("TTY_COMPATIBLE", "1")
    monkeypatch.setenv("COLUMNS", str(columns))
    lines = run_fix(panda, tmp_path, capsys)
    assert max(map(len, lines)) <= columns
    text = "\n".join(lines)
    assert _BOX_DRAWING.search(text)  # a terminal gets rich's borders
    # a wide terminal shows every column, a narrow one keeps the first ones
    header = next(line for line in lines if "mass kg" in line)
    assert ("geometry" in header) == (columns == 200)


def test_duplicated_notes_are_shown_once():
    from urdfinertia.findings import Finding
    from urdfinertia.rules import Rule

    note = Finding(Rule.MESH_REPAIRED, "a", "collision[0]: holes closed", None,
                   "collision[0]")
    r = LinkResult("a", "untouched", "leave", (note, note), because=Rule.NO_GEOMETRY)
    assert _notes(r) == ("left as it is: no geometry to recompute from; "
                         "collision[0]: holes closed")


def test_misspelled_option_is_named_once_with_a_suggestion(tmp_path, capsys):
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="a"/></robot>')
    with pytest.raises(SystemExit) as info:
        main(["fix", str(urdf), "--ouput", str(tmp_path / "o.urdf")])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err == ("urdf-inertia: error: fix: unrecognized arguments: --ouput "
                   f"{tmp_path / 'o.urdf'} (did you mean --output?) (see --help)\n")
    assert not (tmp_path / "o.urdf").exists()


def test_no_suggestion_for_an_unlike_option(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["check", str(tmp_path / "r.urdf"), "--zzzzzz"])
    err = capsys.readouterr().err
    assert err.startswith("urdf-inertia: error: check: unrecognized arguments: --zzzzzz")
    assert "did you mean" not in err and "urdf-inertia: error: urdf-inertia" not in err


def test_fix_to_a_terminal_says_how_to_write_a_file(tmp_path, capsys, monkeypatch):
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="a"/></robot>')
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True)
    assert main(["fix", str(urdf)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert "not printing the fixed document on the terminal: write it with -o FILE" in err
    assert list(tmp_path.iterdir()) == [urdf]


def test_fix_as_a_filter_still_prints_the_document(tmp_path, capsys):
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="a"/></robot>')
    assert main(["fix", str(urdf), "-q"]) == 0
    assert capsys.readouterr().out.startswith('<robot name="r">')


def test_check_of_a_clean_fix_prints_one_line_not_an_empty_table(tmp_path, capsys,
                                                                  monkeypatch):
    robots = Path(__file__).parents[2] / "robots"
    fixed = tmp_path / "nm7mar.fixed.urdf"
    assert main(["fix", str(robots / "nm7mar.urdf"), "--spec",
                 str(robots / "nm7mar.inertia.toml"), "-q", "-o", str(fixed)]) == 0
    capsys.readouterr()
    monkeypatch.setenv("COLUMNS", "100")
    assert main(["check", str(fixed)]) == 0
    out = capsys.readouterr().out
    assert "urdf-inertia fix (default) on nm7mar: all 4 link(s) would be kept as written" \
        in out
    assert "+--" not in out and "|" not in out  # no table when nothing is to be said
