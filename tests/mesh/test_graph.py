"""meshgraph: fast unique rows, vertex welding, edge tables and vertex splitting."""

import numpy as np
import pytest

from urdfinertia.mesh.repair.graph import (
    _unique_float_rows,
    cancel_duplicate_faces,
    edge_table,
    sort_order,
    split_vertices,
    unique_rows,
    weld_vertices,
)


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


def _soup(rng, n_faces=3000):
    """A triangle soup: each corner its own row, vertices shared by value (STL-like)."""
    points = np.round(rng.normal(size=(n_faces // 2, 3)), 3)
    points[:5] = [[0.0, 1.0, 2.0], [-0.0, 1.0, 2.0], [0.0, -0.0, 0.0], [0.0, 0.0, 0.0],
                  [1e-300, 0.0, 0.0]]
    rows = points[rng.integers(0, len(points), size=3 * n_faces)]
    rows[:5] = points[:5]
    return rows


def test_hashed_unique_matches_numpy_including_signed_zeros(rng):
    rows = _soup(rng)
    got = _unique_float_rows(rows)
    assert got is not None
    uniq, inverse, counts = got
    ref, ref_inv, ref_counts = np.unique(rows, axis=0, return_inverse=True,
                                         return_counts=True)
    np.testing.assert_array_equal(uniq, ref)  # -0.0 == 0.0: one row
    np.testing.assert_array_equal(inverse, ref_inv.reshape(-1))
    np.testing.assert_array_equal(counts, ref_counts)
    # the first occurrence represents its group, as the stable lexicographic sort has it
    np.testing.assert_array_equal(np.signbit(uniq), np.signbit(unique_rows(rows)[0]))


def test_hashed_unique_falls_back_on_a_collision(rng, monkeypatch):
    import urdfinertia.mesh.repair.graph as mg

    rows = _soup(rng, 300)
    monkeypatch.setattr(mg, "_MIX", np.zeros(2, dtype=np.uint64))  # every hash equal
    assert mg._unique_float_rows(rows) is None


def test_weld_is_the_same_for_soup_and_indexed_input(rng):
    rows = _soup(rng)
    soup_faces = np.arange(len(rows)).reshape(-1, 3)
    uniq, inverse, _ = np.unique(rows, axis=0, return_inverse=True, return_counts=True)
    indexed = weld_vertices(uniq, inverse.reshape(-1, 3), 0.0)
    welded = weld_vertices(rows, soup_faces, 0.0)
    np.testing.assert_array_equal(welded[0], indexed[0])
    np.testing.assert_array_equal(welded[1], indexed[1])


@pytest.mark.parametrize("shared", [False, True])
def test_split_vertices_matches_sorting_keys(rng, shared):
    n = 60
    faces = rng.integers(0, 40, size=(80, 3))  # vertices 40..59 unused
    label = np.repeat(np.arange(4), 20)
    if not shared:  # each label on its own vertices
        faces = faces % 10 + 10 * label[:, None]
    vertex, local, bounds = split_vertices(n, faces, label, 4)
    key = label[:, None] * n + faces
    uniq, ref_local = np.unique(key, return_inverse=True)
    np.testing.assert_array_equal(vertex, uniq % n)
    np.testing.assert_array_equal(local, ref_local.reshape(-1, 3))
    np.testing.assert_array_equal(bounds, np.searchsorted(uniq, np.arange(5) * n))


def test_edge_table_order_groups_half_edges(rng):
    faces = rng.integers(0, 30, size=(200, 3))
    table = edge_table(faces)
    assert np.all(np.diff(table.edge_id[table.order]) >= 0)
    assert sorted(table.order.tolist()) == list(range(3 * len(faces)))
    tail = faces.reshape(-1)
    head = np.roll(faces, -1, axis=1).reshape(-1)
    np.testing.assert_array_equal(table.edges[table.edge_id],
                                  np.sort(np.stack([tail, head], axis=1), axis=1))


@pytest.mark.parametrize("high", [50, 2**40, 2**62])  # packed, packed, too wide to pack
@pytest.mark.parametrize("dtype", [np.int64, np.int32, np.uint64])
def test_sort_order_is_the_stable_argsort(rng, high, dtype):
    if np.iinfo(dtype).max < high:
        pytest.skip("keys do not fit the type")
    key = rng.integers(0, high, size=5000).astype(dtype)
    key[100:200] = key[0]  # many ties: their order must be the positions'
    np.testing.assert_array_equal(sort_order(key), np.argsort(key, kind="stable"))
    assert len(sort_order(key[:0])) == 0


def test_edge_table_is_that_of_the_generic_unique(rng):
    faces = rng.integers(0, 30, size=(200, 3))
    table = edge_table(faces)
    tail = faces.reshape(-1)
    head = np.roll(faces, -1, axis=1).reshape(-1)
    edges, edge_id, _ = unique_rows(np.sort(np.stack([tail, head], axis=1), axis=1))
    np.testing.assert_array_equal(table.edges, edges)
    np.testing.assert_array_equal(table.edge_id, edge_id)
    np.testing.assert_array_equal(table.order, np.argsort(edge_id, kind="stable"))
    np.testing.assert_array_equal(table.forward, tail < head)


def test_cancel_duplicate_faces_parity():
    faces = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1],  # one triangle three times
                      [3, 4, 5], [5, 4, 3],  # a pair of opposite copies: cancels
                      [6, 8, 7]])
    out, repeats, cancelled = cancel_duplicate_faces(faces)
    np.testing.assert_array_equal(out, [[0, 1, 2], [6, 8, 7]])
    assert (repeats, cancelled) == (2, 1)


def test_first_occurrences_keep_the_first_of_each_distinct_row():
    from urdfinertia.mesh.repair.graph import first_occurrences

    rng = np.random.default_rng(5)
    base = rng.normal(size=(50, 3))
    rows = base[rng.integers(0, 50, size=400)]
    rows[7] = -0.0  # -0.0 and 0.0 are one value
    rows[9] = 0.0
    got = first_occurrences(rows)
    _, want = np.unique(rows + 0.0, axis=0, return_index=True)
    np.testing.assert_array_equal(got, np.sort(want))
    assert len(first_occurrences(np.zeros((0, 3)))) == 0
