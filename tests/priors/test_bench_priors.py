"""scripts/bench_priors.py's measurement: a record holds what the priors need, and the
features read back from it are those the live robot gives (what ``--check`` and ``fix``
compute)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.cache.library import mesh_library
from urdfinertia.descriptions.formats import read_description
from urdfinertia.priors.features import robot_features

SCRIPTS = Path(__file__).resolve().parents[2] / "scripts"


@pytest.fixture(scope="module")
def scripts():
    sys.path.insert(0, str(SCRIPTS))
    try:
        import priors_check
        import priors_corpus
        import priors_fit

        yield priors_corpus, priors_fit, priors_check
    finally:
        sys.path.remove(str(SCRIPTS))


def test_a_record_reads_back_to_the_live_features(scripts, erd_dir):
    priors_corpus, priors_fit, priors_check = scripts
    path = erd_dir / "robots" / "double_pendulum_description" / "urdf" / "double_pendulum.urdf"
    meshes = mesh_library({"example-robot-data": erd_dir})
    record = priors_corpus.measure_file("example-robot-data", path, set(), meshes)
    assert record is not None
    assert [s["link"] for s in record["samples"]] == ["base_link", "link1", "link2"]
    for s in record["samples"]:
        assert s["unique"]
        assert 0 <= s["nomass"] < len(s["candidates"]) and 0 <= s["kept"] < len(s["candidates"])
        assert all(c["volume"] > 0 for c in s["candidates"])
        # the default fix with the tensor withheld, as bench_cad measures it
        assert s["tool"] is not None and s["tool"]["error"] >= 0
    # the links that move get a mass from fix with every inertial withheld
    assert [s["fix_mass"] is not None for s in record["samples"]] == [False, True, True]
    corpus = priors_fit.corpus_rows([record])
    robot, _ = read_description(path)
    live = robot_features(robot)
    assert corpus.kinds == [live.kind]
    for row in corpus.rows:
        f = priors_check.link_prior_features(robot.link(row.link), meshes, path.parent, live)
        assert f is not None
        for name, value in f.__dict__.items():
            got = getattr(row.features, name)
            if isinstance(value, float):
                assert got == pytest.approx(value, rel=1e-9), name
            else:
                assert got == value, name
        assert row.mass == pytest.approx(robot.link(row.link).inertial.mass)
        t = row.tensor
        assert t is not None and np.allclose(t.com, robot.link(row.link).inertial.origin.xyz)
