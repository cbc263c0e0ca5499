"""One answer on the hand-made failure classes of ``tests/data/verdict``: ``check``'s plan
is what ``fix`` does, their exit codes agree, ``check --strict`` passes on ``fix``'s output
and a second ``fix`` changes nothing."""

from __future__ import annotations

from pathlib import Path

import pytest

import urdfinertia
from urdfinertia.cli import main
from urdfinertia.plan.results import Status

DATA = Path(__file__).resolve().parent / "data" / "verdict"
FIXTURES = sorted(p.name for p in DATA.glob("*.urdf"))


def answer(r) -> tuple:  # noqa: ANN001
    return (r.name, r.action, r.status, r.why)


@pytest.mark.parametrize("name", FIXTURES)
def test_check_and_fix_agree_and_fix_converges(name, tmp_path, capsys):
    path = DATA / name
    checked = urdfinertia.check(path)
    fixed = urdfinertia.fix(path)
    assert [answer(r) for r in checked.links] == [answer(r) for r in fixed.links]
    left = [r.name for r in fixed.links if r.status == Status.LEFT]
    out = tmp_path / name
    code = main(["fix", str(path), "-o", str(out), "-q"])
    assert code == (1 if left else 0), capsys.readouterr().err
    assert (checked.exit_code() == 1) == bool(left or any(
        f.severity == "error" for f in checked.findings))
    after = urdfinertia.check(out)
    assert after.exit_code(strict=True) == 0, [f.describe() for f in after.failing(True)]
    again = tmp_path / ("again-" + name)
    assert main(["fix", str(out), "-o", str(again), "-q"]) == 0
    assert again.read_bytes() == out.read_bytes()


def test_a_nan_tensor_keeps_its_mass_in_every_command(tmp_path):
    """``ixx="nan"`` on a 1 kg link: check plans the tensor's recompute with mass and CoM
    kept; fix writes 1 kg (not a density's mass); compare and explain say the same."""
    path = DATA / "nan_tensor.urdf"
    plan = urdfinertia.check(path).link("arm")
    result = urdfinertia.fix(path).link("arm")
    assert plan.action == result.action == "recompute"
    assert set(result.kept) == {"mass", "com"} and result.after.mass == 1.0
    b = urdfinertia.explain(path, "arm")
    assert b.total.mass == 1.0 and b.decision == result.decision
    (row,) = [c for c in urdfinertia.compare(path) if c.link == "arm"]
    assert row.decision == result.planned
