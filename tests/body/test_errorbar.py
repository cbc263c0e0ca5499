"""The error bar of a derived tensor: read from the kind of geometry, its role and the
centroid-to-CoM offset, the finest calibrated cell first."""

from __future__ import annotations

import pytest

from urdfinertia.body.errorbar import (
    BANDS,
    DENSE,
    DENSE_CELL,
    MODEL_P80,
    OFFSET_EDGES,
    is_dense,
    lookup_band,
    offset_bin,
    tensor_error_bar,
)

CELLS = {("mesh", "visual", 0): 0.2, ("mesh", None, 0): 0.3, (None, None, 0): 0.5,
         (None, None, 1): 0.6, (None, None, 2): 0.9, (None, None, 3): 1.0}


def test_offset_bins_follow_the_edges():
    assert offset_bin(0.0) == 0
    assert offset_bin(OFFSET_EDGES[0]) == 1
    assert offset_bin(10.0) == len(OFFSET_EDGES)


@pytest.mark.parametrize(("kind", "role", "band"), [
    ("mesh", "visual", 0.2),       # its own cell
    ("mesh", "collision", 0.3),    # the kind's cell, every role
    ("mesh", "geom", 0.3),         # MuJoCo's counted geoms are collision geometry
    ("primitive", "visual", 0.5),  # every kind
    (None, None, 0.5),
])
def test_the_finest_calibrated_cell_gives_the_band(kind, role, band):
    assert lookup_band(CELLS, kind, role, 0.0) == band


def test_every_offset_bin_has_a_band_for_every_kind():
    for b in range(len(OFFSET_EDGES) + 1):
        assert (None, None, b) in BANDS
    for kind in ("primitive", "hull", "mesh", None):
        for offset in (0.0, 0.05, 0.5):
            assert 0 < lookup_band(BANDS, kind, "visual", offset) < 5


def test_error_bar_says_its_kind_and_basis():
    bar = tensor_error_bar(0.01, 1.0, "mesh", "visual")
    assert bar.basis == "offset" and bar.kind == "mesh"
    assert bar.band == lookup_band(BANDS, "mesh", "visual", 0.01)
    assert "detailed mesh" in str(bar) and bar.as_dict()["kind"] == "mesh"
    model = tensor_error_bar(None, 1.0, "hull", "collision")
    assert model.basis == "model" and model.band == MODEL_P80


def test_a_dense_geometry_takes_the_dense_band_whatever_its_offset():
    # 2 kg in 0.2 l is 10000 kg/m^3: denser than solid titanium, the geometry misses volume
    cells = {**CELLS, DENSE_CELL: 3.0}
    assert is_dense(10000.0) and not is_dense(DENSE) and not is_dense(None)
    assert lookup_band(cells, "mesh", "visual", 0.0, density=10000.0) == 3.0
    assert lookup_band(cells, "mesh", "visual", 0.0, density=2000.0) == 0.2
    # without a calibrated dense cell, the offset cells answer
    assert lookup_band(CELLS, "mesh", "visual", 0.0, density=10000.0) == 0.2


def test_error_bar_of_a_dense_geometry_says_so():
    bar = tensor_error_bar(0.01, 1.0, "mesh", "visual", density=10000.0)
    assert bar.basis == "density" and bar.band == BANDS[DENSE_CELL]
    assert "implied density 10000 kg/m³" in str(bar)
    assert bar.as_dict()["density"] == 10000.0
    light = tensor_error_bar(0.01, 1.0, "mesh", "visual", density=2000.0)
    assert light.basis == "offset" and "centroid 1.0 %" in str(light)


def test_fix_gives_a_dense_geometry_the_dense_band():
    from pathlib import Path

    from urdfinertia.body.options import FixOptions
    from urdfinertia.plan.fix import fix_file

    result = fix_file(Path(__file__).parents[1] / "data" / "geometry" / "dense.urdf",
                      FixOptions())
    housing, arm = result.link("housing"), result.link("arm")
    # 5 kg in a 0.1 x 0.1 x 0.05 m box: 10000 kg/m^3
    assert housing.error_bar.density == pytest.approx(10000.0)
    assert housing.error_bar.basis == "density"
    assert housing.error_bar.band == BANDS[DENSE_CELL]
    assert "implied density 10000 kg/m³" in str(housing.error_bar)
    # 2 kg in 0.2 x 0.1 x 0.05 m: 2000 kg/m^3, read from its kind and offset
    assert arm.error_bar.basis == "offset" and arm.error_bar.density == pytest.approx(2000.0)
    assert arm.error_bar.band < housing.error_bar.band
