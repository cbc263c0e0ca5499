"""meshgraph.unique_rows against numpy's row-wise unique (the slow reference)."""

import numpy as np
import pytest

from urdfinertia.meshgraph import unique_rows


@pytest.mark.parametrize("kind", ["small_int", "big_int", "float"])
def test_unique_rows_matches_numpy(kind, rng):
    if kind == "small_int":
        rows = rng.integers(0, 20, size=(500, 3))
    elif kind == "big_int":
        rows = rng.integers(0, 2**40, size=(300, 2))
        rows = np.concatenate([rows, rows[:50]])
    else:
        rows = np.round(rng.normal(size=(400, 3)), 1)
    uniq, inverse, counts = unique_rows(rows)
    ref, ref_inv, ref_counts = np.unique(rows, axis=0, return_inverse=True,
                                         return_counts=True)
    np.testing.assert_array_equal(uniq, ref)
    np.testing.assert_array_equal(inverse, ref_inv.reshape(-1))
    np.testing.assert_array_equal(counts, ref_counts)
    np.testing.assert_array_equal(uniq[inverse], rows)
