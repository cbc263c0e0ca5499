"""atomic.py: temporary file + fsync + rename, backups, symbolic links, permissions."""

from __future__ import annotations

import os
import stat

import pytest

from urdfinertia import atomic
from urdfinertia.atomic import atomic_write_bytes, write_in_place
from urdfinertia.errors import OutputError


def listing(folder) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_new_file_written_with_umask_permissions(tmp_path):
    old = os.umask(0o027)
    try:
        written = atomic_write_bytes(tmp_path / "out.urdf", b"data")
    finally:
        os.umask(old)
    assert written == tmp_path / "out.urdf"
    assert (tmp_path / "out.urdf").read_bytes() == b"data"
    assert stat.S_IMODE((tmp_path / "out.urdf").stat().st_mode) == 0o640
    assert listing(tmp_path) == ["out.urdf"]


def test_existing_file_keeps_its_mode(tmp_path):
    target = tmp_path / "out.urdf"
    target.write_bytes(b"old")
    target.chmod(0o604)
    atomic_write_bytes(target, b"new")
    assert target.read_bytes() == b"new"
    assert stat.S_IMODE(target.stat().st_mode) == 0o604


def test_existing_file_is_replaced_not_rewritten(tmp_path):
    """A reader holding the old file keeps the old bytes: proof of rename, not truncate."""
    target = tmp_path / "out.urdf"
    target.write_bytes(b"old contents")
    with open(target, "rb") as held:
        atomic_write_bytes(target, b"new")
        assert held.read() == b"old contents"
    assert target.read_bytes() == b"new"


def test_failure_during_write_leaves_target_and_no_temporary(tmp_path, monkeypatch):
    target = tmp_path / "out.urdf"
    target.write_bytes(b"precious")

    def broken_fsync(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "fsync", broken_fsync)
    with pytest.raises(OutputError, match="No space left on device") as exc:
        atomic_write_bytes(target, b"half")
    assert exc.value.file == str(target)
    assert target.read_bytes() == b"precious"
    assert listing(tmp_path) == ["out.urdf"]


def test_interrupt_during_write_removes_temporary(tmp_path, monkeypatch):
    target = tmp_path / "out.urdf"

    def interrupted(src, dst):
        raise KeyboardInterrupt

    monkeypatch.setattr(atomic.os, "replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        atomic_write_bytes(target, b"data")
    assert listing(tmp_path) == []


def test_missing_folder_is_an_output_error(tmp_path):
    with pytest.raises(OutputError, match="cannot write"):
        atomic_write_bytes(tmp_path / "nope" / "out.urdf", b"x")
    assert listing(tmp_path) == []


def test_symlink_target_is_replaced_link_kept(tmp_path):
    target = tmp_path / "real.urdf"
    target.write_bytes(b"old")
    link = tmp_path / "link.urdf"
    link.symlink_to(target.name)  # relative link
    written = atomic_write_bytes(link, b"new")
    assert written == target
    assert link.is_symlink() and os.readlink(link) == "real.urdf"
    assert target.read_bytes() == b"new"


def test_in_place_keeps_backup(tmp_path):
    target = tmp_path / "r.urdf"
    target.write_bytes(b"version 1")
    target.chmod(0o640)
    assert write_in_place(target, b"version 2") == target
    assert target.read_bytes() == b"version 2"
    backup = tmp_path / "r.urdf.bak"
    assert backup.read_bytes() == b"version 1"
    assert stat.S_IMODE(backup.stat().st_mode) == 0o640  # copied with its mode
    write_in_place(target, b"version 3")
    assert backup.read_bytes() == b"version 2"  # the backup is of the previous run
    assert listing(tmp_path) == ["r.urdf", "r.urdf.bak"]


def test_in_place_through_symlink_chain(tmp_path):
    real = tmp_path / "pkg" / "r.urdf"
    real.parent.mkdir()
    real.write_bytes(b"original")
    middle = tmp_path / "middle.urdf"
    middle.symlink_to(real)
    link = tmp_path / "link.urdf"
    link.symlink_to(middle)
    assert write_in_place(link, b"fixed") == real
    assert real.read_bytes() == b"fixed"
    assert (real.parent / "r.urdf.bak").read_bytes() == b"original"
    assert link.is_symlink() and middle.is_symlink()
    assert listing(tmp_path) == ["link.urdf", "middle.urdf", "pkg"]


def test_in_place_backup_failure_leaves_file(tmp_path, monkeypatch):
    target = tmp_path / "r.urdf"
    target.write_bytes(b"original")

    def no_copy(src, dst):
        raise OSError(5, "Input/output error")

    monkeypatch.setattr(atomic.shutil, "copy2", no_copy)
    with pytest.raises(OutputError, match="cannot write backup"):
        write_in_place(target, b"new")
    assert target.read_bytes() == b"original"
    assert listing(tmp_path) == ["r.urdf"]


def test_in_place_write_failure_keeps_original_and_backup(tmp_path, monkeypatch):
    target = tmp_path / "r.urdf"
    target.write_bytes(b"original")
    real_replace = os.replace

    def replace_only_backup(src, dst):
        if str(dst).endswith(".bak"):
            return real_replace(src, dst)
        raise OSError(30, "Read-only file system")

    monkeypatch.setattr(atomic.os, "replace", replace_only_backup)
    with pytest.raises(OutputError, match="Read-only file system"):
        write_in_place(target, b"new")
    assert target.read_bytes() == b"original"
    assert (tmp_path / "r.urdf.bak").read_bytes() == b"original"
    assert listing(tmp_path) == ["r.urdf", "r.urdf.bak"]


def test_writer_leaves_a_file_holding_the_bytes_untouched(tmp_path):
    target = tmp_path / "out.urdf"
    target.write_bytes(b"same")
    os.utime(target, ns=(1_000_000_000, 1_000_000_000))
    before = target.stat()
    with atomic.OutputWriter() as writer:
        written = writer.write(target, b"same")
    after = target.stat()
    assert written == atomic.Written(target, True) and writer.untouched == 1
    assert (after.st_ino, after.st_mtime_ns) == (before.st_ino, before.st_mtime_ns)


@pytest.mark.parametrize("old", [b"other", b"sam", b"same plus more", None])
def test_writer_replaces_other_bytes_atomically(tmp_path, old):
    target = tmp_path / "out.urdf"
    if old is not None:
        target.write_bytes(old)
        target.chmod(0o604)
    inode = target.stat().st_ino if old is not None else None
    with atomic.OutputWriter() as writer:
        written = writer.write(target, b"same")
    assert written == atomic.Written(target, False) and writer.untouched == 0
    assert target.read_bytes() == b"same"
    assert listing(tmp_path) == ["out.urdf"]
    if old is not None:  # a new file renamed over the old one, its mode kept
        assert target.stat().st_ino != inode
        assert stat.S_IMODE(target.stat().st_mode) == 0o604


def test_writer_syncs_each_folder_once_after_its_files(tmp_path, monkeypatch):
    synced: list = []
    monkeypatch.setattr(atomic, "_fsync_folder", synced.append)
    files: list = []
    real_fsync = os.fsync
    monkeypatch.setattr(atomic.os, "fsync", lambda fd: (files.append(fd), real_fsync(fd)))
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    writer = atomic.OutputWriter()
    for name in ("a/1.urdf", "a/2.urdf", "b/3.urdf"):
        writer.write(tmp_path / name, name.encode())
    assert synced == [] and len(files) == 3  # each file's data, no folder yet
    writer.close()
    assert sorted(synced) == [tmp_path / "a", tmp_path / "b"]
    writer.close()
    assert len(synced) == 2  # nothing new to sync


def test_writer_failure_is_an_output_error_and_leaves_the_old_file(tmp_path, monkeypatch):
    target = tmp_path / "out.urdf"
    target.write_bytes(b"old")

    def fail(*args):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "replace", fail)
    with pytest.raises(OutputError, match="No space left"), atomic.OutputWriter() as writer:
        writer.write(target, b"new")
    assert target.read_bytes() == b"old"
    assert listing(tmp_path) == ["out.urdf"]


def test_writer_follows_a_symlink(tmp_path):
    real = tmp_path / "real.urdf"
    real.write_bytes(b"old")
    link = tmp_path / "link.urdf"
    link.symlink_to(real)
    with atomic.OutputWriter() as writer:
        assert writer.write(link, b"new") == atomic.Written(real, False)
        assert writer.write(link, b"new") == atomic.Written(real, True)
    assert link.is_symlink() and real.read_bytes() == b"new"


def test_writer_is_safe_from_many_threads(tmp_path):
    import concurrent.futures as cf

    names = [f"{i}.urdf" for i in range(40)]
    (tmp_path / "2.urdf").write_bytes(b"2.urdf")  # already holds its bytes
    with atomic.OutputWriter() as writer, cf.ThreadPoolExecutor(8) as pool:
        results = list(pool.map(lambda n: writer.write(tmp_path / n, n.encode()), names))
    assert sum(r.untouched for r in results) == writer.untouched == 1
    assert all((tmp_path / n).read_bytes() == n.encode() for n in names)
    assert listing(tmp_path) == sorted(names)
