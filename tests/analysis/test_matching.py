"""Links of two descriptions matched as converters rename them (``analysis.matching``),
and ``compare --against`` on a renamed copy: every link matched, every difference found,
what cannot be matched listed."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from urdfinertia.analysis.compare import match_files
from urdfinertia.analysis.matching import match_names

NM7MAR = Path(__file__).resolve().parents[2] / "robots" / "nm7mar.urdf"


def test_converter_renamings_are_matched():
    a = ["base-link", "link_3.0", "2nd", "gripper/finger"]
    b = ["base_link", "link_3_0", "_2nd", "finger"]
    m = match_names(a, b)
    assert dict(m.pairs) == dict(zip(a, b, strict=True))
    assert m.only_a == m.only_b == ()
    assert "4 of 4 links matched (4 renamed, as base-link -> base_link)" == m.summary()


def test_prefixes_and_paths_are_dropped():
    a = ["link0", "link1", "hand"]
    b = ["/World/panda/panda_link0", "/World/panda/panda_link1", "/World/panda/panda_hand"]
    assert dict(match_names(a, b).pairs) == dict(zip(a, b, strict=True))


def test_ambiguous_and_absent_names_are_listed_not_guessed():
    m = match_names(["a.b", "a-b", "c"], ["a_b", "d"])
    assert m.pairs == ()
    assert m.only_a == ("a.b", "a-b", "c") and m.only_b == ("a_b", "d")
    assert "only in A: a.b, a-b, c; only in B: a_b, d" in m.summary()


def _renamed_copy(tmp_path: Path) -> Path:
    """NM7MAR with every link renamed as a USD converter would (``.``/``-`` made ``_``,
    the robot's name prefixed) the values unchanged."""
    text = NM7MAR.read_text()
    import re

    names = re.findall(r'<link name="([^"]+)"', text)
    for n in names:
        text = text.replace(f'"{n}"', f'"nm7mar_{n.replace("-", "_").replace(".", "_")}"')
    out = tmp_path / "renamed.urdf"
    out.write_text(text)
    return out


def test_compare_against_a_renamed_copy_matches_every_link(tmp_path):
    other = _renamed_copy(tmp_path)
    comparisons, matching = match_files(NM7MAR, other)
    assert matching.only_a == () and matching.only_b == ()
    assert len(matching.pairs) == len(comparisons)
    assert {c.verdict for c in comparisons} <= {"ok"}, [(c.link, c.verdict, c.note)
                                                       for c in comparisons]
    done = subprocess.run([sys.executable, "-m", "urdfinertia", "compare", "-q", str(NM7MAR),
                           "--against", str(other)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert f"{len(comparisons)} of {len(comparisons)} links matched" in done.stdout


def test_compare_against_lists_what_it_cannot_match(tmp_path):
    text = NM7MAR.read_text().replace('name="link1"', 'name="something_else"')
    other = tmp_path / "other.urdf"
    other.write_text(text)
    comparisons, matching = match_files(NM7MAR, other)
    assert "link1" in matching.only_a and "something_else" in matching.only_b
    missing = {c.link: c.note for c in comparisons if c.verdict == "missing"}
    assert missing["link1"] == "no link of side B matches"
    assert missing["something_else"] == "no link of side A matches"
