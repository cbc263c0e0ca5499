"""The packaged mass prior against its own held-out folds (the saved corpus sample).

``tests/data/priors/sample.json`` is written by ``scripts/bench_priors.py --fixture`` from
the same measurement as ``src/urdfinertia/data/priors.json``: every unique CAD link's
package, target (log10 of its effective density) and terms. Refitting it must give the
file's coefficients, and leaving one package out at a time must give the file's band and
the coverage it records: a stale file, a changed fit or a changed band rule fails here.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.priors import fit
from urdfinertia.priors.data import load_table

SAMPLE = Path(__file__).resolve().parents[1] / "data" / "priors" / "sample.json"


@pytest.fixture(scope="module")
def sample():
    doc = json.loads(SAMPLE.read_text())
    rows, ys, groups, keys, mask = [], [], [], [], []
    for i, (package, y, numeric, categories, also_in) in enumerate(doc["links"]):
        terms = {"intercept": 1.0, **dict(zip(doc["numeric"], numeric, strict=True)),
                 **{doc["categories"][c]: 1.0 for c in categories}}
        # the link itself, then a stand-in in every other package that holds it: a fold
        # leaving that package out must not fit on it (fit.held_out's ``keys``)
        for g, fitted in [(package, True)] + [(other, False) for other in also_in]:
            rows.append(terms)
            ys.append(y)
            groups.append(g)
            keys.append(i)
            mask.append(fitted)
    mask_a = np.array(mask)
    held = fit.held_out(rows, np.array(ys), groups, doc["ridge"], fit_mask=mask_a, keys=keys)
    return {"doc": doc, "rows": rows, "y": np.array(ys), "groups": np.array(groups),
            "mask": mask_a, "held": held}


def test_the_sample_is_the_files_own(sample):
    table = load_table()
    assert sample["doc"]["ridge"] == table.mass["ridge"]
    assert sample["doc"]["level"] == table.mass["band"]["level"]
    assert int(sample["mask"].sum()) == table.produced["figures"]["tensor"]["links"]


def test_refitting_gives_the_files_coefficients(sample):
    m = sample["mask"]
    rows = [r for r, ok in zip(sample["rows"], m, strict=True) if ok]
    got = fit.fit_ridge(rows, sample["y"][m], fit.package_weights(sample["groups"][m]),
                        sample["doc"]["ridge"])
    want = load_table().mass["coefficients"]
    assert set(got) == set(want)
    for k, v in want.items():
        assert got[k] == pytest.approx(v, abs=1e-4), k


def test_held_out_folds_give_the_files_band_and_coverage(sample):
    table = load_table()
    m = sample["mask"]
    res = (sample["y"] - sample["held"])[m]
    groups = sample["groups"][m]
    band = table.mass["band"]
    lo, hi = fit.quantile_band(res, band["level"])
    assert lo == pytest.approx(band["low"], abs=1e-3)
    assert hi == pytest.approx(band["high"], abs=1e-3)
    cov = fit.nested_coverage(res, list(groups), band["level"])
    pooled = float(np.mean(np.concatenate(list(cov.values()))))
    recorded = table.produced["figures"]["mass"]["link_coverage"]
    assert pooled == pytest.approx(recorded, abs=1.5 / len(res))  # one link of rounding
    # the stated target: 75-85 % of links inside bands fitted on the other packages
    assert 0.75 <= pooled <= 0.85
    # and the held-out median error is the file's
    err = np.abs(10.0 ** -res - 1.0)
    assert float(np.median(err)) == pytest.approx(
        table.produced["figures"]["mass"]["link_error_median"], abs=2e-3)


def test_held_out_predictions_are_deterministic(sample):
    keys = []
    for i, (_, _, _, _, also_in) in enumerate(sample["doc"]["links"]):
        keys += [i] * (1 + len(also_in))
    again = fit.held_out(sample["rows"], sample["y"], list(sample["groups"]),
                         sample["doc"]["ridge"], fit_mask=sample["mask"], keys=keys)
    np.testing.assert_array_equal(again, sample["held"])
