"""The release the integrations name: one version everywhere, a tag the docs pin.

pre-commit never updates a branch ``rev`` and an Action used at a branch moves under its
users, so the docs show the release tag; a version bump that forgets one of these fails.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import yaml

import urdfinertia

ROOT = Path(__file__).resolve().parents[2]


def test_one_version_everywhere():
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert urdfinertia.__version__ == version
    assert re.search(rf"^## \[{re.escape(version)}\] - \d{{4}}-\d\d-\d\d$",
                     (ROOT / "CHANGELOG.md").read_text(), re.M)


def test_the_integrations_are_used_at_the_release_tag():
    tag = f"v{urdfinertia.__version__}"
    for page in (ROOT / "docs" / "ci.md", ROOT / "README.md"):
        text = page.read_text()
        assert f"urdfinertia@{tag}" in text and f"rev: {tag}" in text, page.name
        assert "@main" not in text and "rev: main" not in text, page.name
    assert f"urdfinertia@{tag}" in (ROOT / "action.yml").read_text()


def test_the_hook_takes_every_format_and_checks_includes_through_their_robots():
    (hook,) = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())
    files = re.compile(hook["files"])
    for name in ("r.urdf", "r.xacro", "m.sdf", "m.xml", "a.usd", "a.usda", "a.usdc",
                 "a.usdz"):
        assert files.search(f"robots/{name}"), name
    assert not files.search("notes.txt")
    assert "--includers" in hook["entry"] and "--skip-unknown-formats" in hook["entry"]
    action = (ROOT / "scripts" / "action_check.sh").read_text()
    assert "--includers" in action
    assert all(f"'*.{s}'" in action for s in ("usd", "usda", "usdc", "usdz"))
