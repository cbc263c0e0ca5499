"""The persistent mesh cache: exact round trips, keys, distrust of bad entries, size bound."""

from __future__ import annotations

import os

import numpy as np
import pytest

from urdfinertia.cache import store as cache_mod
from urdfinertia.cache.store import (
    CACHE_FORMAT,
    MAGIC,
    SUBDIR,
    SolidsCache,
    decode_entry,
    default_cache_dir,
    encode_entry,
    entry_key,
    pack,
    unpack,
)
from urdfinertia.errors import MeshError
from urdfinertia.mesh.solids import MeshSolids, Solid


def random_solids(rng: np.random.Generator, k: int = 2) -> MeshSolids:
    out = []
    for i in range(k):
        a = rng.normal(size=(3, 3))
        out.append(Solid(float(rng.uniform(0.1, 2.0)), rng.normal(size=3), a @ a.T,
                         f"method {i}", None if i else 0.01, (f"note {i}",)))
    return MeshSolids(tuple(out), ("2 bodies",))


def assert_same(a: MeshSolids, b: MeshSolids) -> None:
    assert a.notes == b.notes
    assert len(a.solids) == len(b.solids)
    for x, y in zip(a.solids, b.solids, strict=True):
        assert x.volume == y.volume  # exact: float64 stored as float64
        np.testing.assert_array_equal(x.first, y.first)
        np.testing.assert_array_equal(x.second, y.second)
        assert (x.method, x.error_estimate, x.notes) == (y.method, y.error_estimate, y.notes)


@pytest.fixture
def store(tmp_path) -> SolidsCache:
    return SolidsCache(tmp_path / "cache", max_bytes=1 << 20)


def test_round_trip_is_exact(store, rng):
    solids = random_solids(rng)
    key = entry_key(b"mesh bytes", ".stl")
    store.put(key, solids, faces=1234)
    found = store.get(key)
    assert found is not None
    assert_same(found[0], solids)
    assert found[1] == 1234
    assert (store.hits, store.misses) == (1, 0)


def test_key_depends_on_content_and_format_not_name():
    assert entry_key(b"abc", ".stl") == entry_key(b"abc", ".STL")
    assert entry_key(b"abc", ".stl") != entry_key(b"abd", ".stl")
    assert entry_key(b"abc", ".stl") != entry_key(b"abc", ".obj")


def test_key_depends_on_the_code(monkeypatch):
    """Any source edit invalidates every entry: the key includes the code digest."""
    before = entry_key(b"abc", ".stl")
    monkeypatch.setattr(cache_mod, "code_digest", lambda: "other code")
    assert entry_key(b"abc", ".stl") != before


def test_code_digest_covers_every_module_of_every_subpackage(tmp_path, monkeypatch):
    """The one versioning rule sees an edit in a nested module (here: mesh/repair)."""
    import shutil

    from urdfinertia.cache import version

    copy = tmp_path / "urdfinertia"
    shutil.copytree(version._PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(version, "_PACKAGE", copy)
    version.code_digest.cache_clear()
    before = version.code_digest()
    target = copy / "mesh" / "repair" / "holes.py"
    target.write_text(target.read_text() + "\n# an edit\n")
    version.code_digest.cache_clear()
    after = version.code_digest()
    version.code_digest.cache_clear()
    assert before != after


def test_missing_entry_is_a_miss(store):
    assert store.get(entry_key(b"nothing", ".stl")) is None
    assert store.misses == 1


@pytest.mark.parametrize("damage", [
    "garbage", "truncated", "foreign key", "other format", "nan", "negative volume",
    "short numbers", "extra field", "zero faces", "asymmetric", "header not an object",
])
def test_bad_entries_are_ignored(store, rng, damage):
    solids = random_solids(rng)
    key = entry_key(b"mesh", ".stl")
    good = encode_entry(solids, 10, key)
    header, numbers = unpack(good)
    if damage == "garbage":
        data = bytes(rng.integers(0, 256, size=500, dtype=np.uint8))
    elif damage == "truncated":
        data = good[: len(good) - 12]
    elif damage == "foreign key":  # a valid entry copied under another name
        data = encode_entry(solids, 10, entry_key(b"other mesh", ".stl"))
    elif damage == "other format":
        data = pack(header | {"format": "something/else"}, numbers)
    elif damage == "nan":
        data = pack(header, np.where(np.arange(len(numbers)) == 3, np.nan, numbers))
    elif damage == "negative volume":
        data = pack(header, np.concatenate([-numbers[:2], numbers[2:]]))
    elif damage == "short numbers":
        data = pack(header, numbers[:-9])
    elif damage == "extra field":
        header["solids"][0]["evil"] = 1
        data = pack(header, numbers)
    elif damage == "zero faces":
        data = pack(header | {"faces": 0}, numbers)
    elif damage == "asymmetric":
        numbers = numbers.copy()
        numbers[-8] += 1.0  # second[1][0, 1]
        data = pack(header, numbers)
    else:
        head = b"[1, 2]"
        data = MAGIC + len(head).to_bytes(4, "little") + head
    assert decode_entry(good, key) is not None
    path = store.path(key)
    path.parent.mkdir(parents=True)
    path.write_bytes(data)
    assert store.get(key) is None


def test_a_pickle_under_an_entry_name_is_never_loaded(store, tmp_path):
    """Loading this pickle would create a file: the cache must not even try."""
    import builtins
    import pickle

    witness = tmp_path / "unpickled"

    class Payload:
        def __reduce__(self):
            return (builtins.open, (str(witness), "w"))

    key = entry_key(b"mesh", ".stl")
    path = store.path(key)
    path.parent.mkdir(parents=True)
    path.write_bytes(pickle.dumps(Payload()))
    assert store.get(key) is None
    assert not witness.exists()


def test_rejected_meshes_are_remembered_as_their_message(store):
    key = entry_key(b"flat", ".stl")
    store.put(key, MeshError("mesh encloses no volume"), faces=12)
    found, faces = store.get(key)
    assert isinstance(found, MeshError)
    assert (found.cause, found.file, faces) == ("mesh encloses no volume", None, 12)


def test_header_names_this_format(rng):
    header, _ = unpack(encode_entry(random_solids(rng), 10, "k"))
    assert header["format"] == CACHE_FORMAT


def test_prune_deletes_least_recently_used_first(store, rng):
    keys = [entry_key(bytes([i]), ".stl") for i in range(6)]
    for i, key in enumerate(keys):
        store.put(key, random_solids(rng), 10)
        os.utime(store.path(key), (1000.0 + i, 1000.0 + i))
    store.get(keys[0])  # a hit makes the oldest entry the most recently used
    size = store.path(keys[1]).stat().st_size
    freed = store.prune(max_bytes=3 * size + size // 2)
    left = {p.stem for p, _, _ in store.entries()}
    assert left == {keys[0], keys[4], keys[5]}
    assert freed > 0
    assert store.size() <= 3 * size + size // 2


def test_prune_leaves_other_files_alone(store, rng):
    other = store.root / "notes.txt"
    store.root.mkdir(parents=True)
    other.write_text("mine")
    store.put(entry_key(b"x", ".stl"), random_solids(rng), 10)
    store.prune(max_bytes=0)
    assert other.read_text() == "mine"
    assert store.entries() == []
    assert (store.root / SUBDIR).is_dir()


def test_unwritable_cache_turns_itself_off(tmp_path, rng):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    store = SolidsCache(blocker / "cache")
    store.put(entry_key(b"x", ".stl"), random_solids(rng), 10)
    assert not store.enabled
    assert store.warnings and "cache disabled" in store.warnings[0]
    assert store.get(entry_key(b"x", ".stl")) is None


def test_default_location_follows_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(tmp_path / "here"))
    assert default_cache_dir() == tmp_path / "here"
    monkeypatch.delenv("URDFINERTIA_CACHE_DIR")
    assert "urdfinertia" in str(default_cache_dir())


def test_keys_are_never_read_from_special_or_huge_files(tmp_path):
    import threading

    from urdfinertia.cache.store import file_entry_key

    fifo = tmp_path / "pipe.stl"
    os.mkfifo(fifo)
    found: list[object] = []
    worker = threading.Thread(target=lambda: found.append(file_entry_key(fifo, 1 << 20)),
                              daemon=True)
    worker.start()
    worker.join(30)  # a hang guard, not a speed check: opening a FIFO blocks forever
    assert found == [None]
    big = tmp_path / "big.stl"
    big.write_bytes(b"x" * 2000)
    assert file_entry_key(big, 1000) is None
    assert file_entry_key(big, 2000) == entry_key(b"x" * 2000, ".stl")


def test_digest_memo_skips_unchanged_files_and_sees_edits(tmp_path, monkeypatch):
    from urdfinertia.cache import digests

    monkeypatch.setattr(digests, "RACY_SECONDS", -1.0)  # remember even brand-new files
    reads: list[str] = []
    real = digests.file_digest
    monkeypatch.setattr(digests, "file_digest", lambda p, m: reads.append(p) or real(p, m))
    mesh = tmp_path / "m.stl"
    mesh.write_bytes(b"a" * 100)
    memo = digests.FileDigests(tmp_path / "d.json")
    first = memo.digest(mesh, 1000)
    assert memo.digest(mesh, 1000) == first == digests.content_digest(b"a" * 100)
    assert len(reads) == 1
    memo.save()
    again = digests.FileDigests(tmp_path / "d.json")
    assert again.digest(mesh, 1000) == first
    assert len(reads) == 1  # from the saved memo
    mesh.write_bytes(b"b" * 100)  # same size: the times tell it changed
    os.utime(mesh, ns=(10**18, 10**18))
    assert again.digest(mesh, 1000) == digests.content_digest(b"b" * 100)
    assert len(reads) == 2


def test_recently_changed_files_are_not_remembered(tmp_path):
    from urdfinertia.cache import digests

    mesh = tmp_path / "m.stl"
    mesh.write_bytes(b"abc")
    memo = digests.FileDigests(tmp_path / "d.json")
    memo.digest(mesh, 1000)
    memo.save()
    assert not (tmp_path / "d.json").exists()  # within RACY_SECONDS of its change time


@pytest.mark.parametrize("text", ["not json", '{"format": "other", "files": {}}',
                                  '{"format": "urdfinertia-digests/1", "files": []}',
                                  '{"format": "urdfinertia-digests/1", "files": {"x": 5}}'])
def test_a_bad_digest_memo_is_ignored(tmp_path, text):
    from urdfinertia.cache import digests

    mesh = tmp_path / "m.stl"
    mesh.write_bytes(b"abc")
    (tmp_path / "d.json").write_text(text)
    assert digests.FileDigests(tmp_path / "d.json").digest(mesh, 1000) == \
        digests.content_digest(b"abc")


def test_a_warm_run_imports_no_numerical_or_terminal_library():
    """Structure, not speed: the modules a whole-file cache hit runs through stay light."""
    import subprocess
    import sys

    code = ("import sys\n"
            "from urdfinertia.batch.run import BatchSettings, run_batch\n"
            "from urdfinertia.batch.inputs import collect_jobs\n"
            "from urdfinertia.body.options import FixOptions\n"
            "import urdfinertia.cli, urdfinertia.cli.fix\n"
            "heavy = {'numpy', 'lxml', 'rich', 'trimesh', 'scipy', 'multiprocessing'}\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_prune_skips_the_scan_when_nothing_was_written(store, rng, monkeypatch):
    store.put(entry_key(b"x", ".stl"), random_solids(rng), 10)
    store.prune()
    quiet = SolidsCache(store.root)  # a warm run: hits only
    monkeypatch.setattr(quiet, "_scan", lambda: pytest.fail("scanned"))
    assert quiet.prune() == 0
    smaller = SolidsCache(store.root)  # a lower bound than the size counted: scanned
    assert smaller.prune(max_bytes=1) > 0
    assert smaller.entries() == []
