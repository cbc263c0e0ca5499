"""priors/model.py and data.py: the packaged table is read, checked and used as written."""

import copy
import json
import math

import pytest

from urdfinertia.priors.data import PriorsDataError, PriorTable, data_text, load_table
from urdfinertia.priors.features import (
    MATERIAL_HINTS,
    PART_KINDS,
    ROBOT_KINDS,
    LinkFeatures,
)
from urdfinertia.priors.model import log_density, mass_prior, robot_total
from urdfinertia.priors.structure import MODELS
from urdfinertia.priors.terms import NUMERIC, term_values

GEOMETRIES = ("primitive", "hull", "mesh")
ROLES = ("collision", "visual", "geom")


def features(**kw) -> LinkFeatures:
    base = dict(robot_kind="humanoid", part="leg", geometry="mesh", role="visual",
                volume=0.0015, fill=0.4, diagonal=0.3, depth_share=0.5, below=0.2, joints=2,
                extent=1.2, hints="", excess=1.0)
    base.update(kw)
    return LinkFeatures(**base)


def test_the_packaged_file_says_what_produced_it():
    table = load_table()
    produced = table.produced
    assert produced["command"].startswith("python scripts/bench_priors.py")
    assert produced["measured"]["command"].startswith("python scripts/bench_priors.py")
    assert produced["urdfinertia"]
    corpus = produced["corpus"]
    assert sum(p["links"] for p in corpus.values()) == produced["figures"]["tensor"]["links"]
    assert len(corpus) >= 10
    # the versions of the packages the corpus came from are recorded
    assert "example-robot-data" in produced["measured"]["versions"]


def test_every_coefficient_is_a_term_the_features_make():
    known = {"intercept", *NUMERIC}
    for prefix, values in (("robot", ROBOT_KINDS), ("part", PART_KINDS),
                           ("geometry", GEOMETRIES), ("role", ROLES),
                           ("hint", MATERIAL_HINTS)):
        known |= {f"{prefix}:{v}" for v in values}
    coefficients = load_table().mass["coefficients"]
    assert set(coefficients) <= known
    assert all(math.isfinite(v) for v in coefficients.values())
    cells = load_table().structure["cells"]
    assert "*" in cells and all(c["model"] in MODELS for c in cells.values())


def test_the_prediction_is_the_sum_of_the_tables_terms():
    table = load_table()
    f = features(hints="dense", excess=2.0)
    value, parts = log_density(f, table)
    coefficients = table.mass["coefficients"]
    expected = sum(coefficients.get(k, 0.0) * v for k, v in term_values(f).items())
    assert value == pytest.approx(expected, abs=1e-12)
    assert value == pytest.approx(sum(v for _, v in parts), abs=1e-12)
    assert [abs(v) for _, v in parts] == sorted((abs(v) for _, v in parts), reverse=True)
    p = mass_prior(f, table)
    assert p.density == pytest.approx(10 ** value)
    assert p.mass == pytest.approx(p.density * f.volume)
    band = table.mass["band"]
    assert p.low == pytest.approx(p.mass * 10 ** band["low"])
    assert p.high == pytest.approx(p.mass * 10 ** band["high"])
    assert p.low < p.mass < p.high and p.level == band["level"]
    assert mass_prior(f, table) == p  # deterministic


def test_a_term_the_table_does_not_know_adds_nothing():
    doc = json.loads(data_text())
    doc["mass"]["coefficients"] = {"intercept": 3.0, "log_volume": -0.5}
    table = PriorTable.from_dict(doc)
    p = mass_prior(features(robot_kind="marine", volume=1e-3), table)  # log_volume 0
    assert p.density == pytest.approx(1000.0)


def test_the_robot_total_and_its_band():
    table = load_table()
    links = [mass_prior(features(volume=v, part=part), table)
             for v, part in ((0.004, "base"), (0.002, "leg"), (0.001, "leg"))]
    total = robot_total(links, table)
    assert total.mass == pytest.approx(sum(p.mass for p in links))
    assert total.water == pytest.approx(1000.0 * 0.007)
    rb = table.mass["robot_band"]
    assert total.links == 3 >= rb["min_links"]
    assert total.low == pytest.approx(total.mass * 10 ** rb["low"])
    assert total.high == pytest.approx(total.mass * 10 ** rb["high"])
    assert "at 1000 kg/m³; the prior gives" in total.describe()
    # fewer links than the robot band was measured on: the link band
    one = robot_total(links[:1], table)
    assert one.low == pytest.approx(links[0].low) and one.level == table.mass["band"]["level"]
    with pytest.raises(ValueError, match="no links"):
        robot_total([], table)


@pytest.mark.parametrize("damage", [
    lambda d: d.update(format="other"),
    lambda d: d.update(version=99),
    lambda d: d["mass"].pop("band"),
    lambda d: d.pop("structure"),
])
def test_a_file_of_another_format_or_version_is_refused(damage):
    doc = copy.deepcopy(json.loads(data_text()))
    damage(doc)
    with pytest.raises(PriorsDataError):
        PriorTable.from_dict(doc)


def test_the_table_round_trips():
    table = load_table()
    assert PriorTable.from_dict(table.as_dict()) == table
