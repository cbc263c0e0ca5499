"""Atomic file writes: a temporary file in the target's folder, fsync, rename.

A failed run leaves no half-written output and an existing file is replaced only on
success: the new bytes go to a temporary file next to the target, are flushed to disk,
and the temporary file is renamed over the target (`os.replace`, atomic on POSIX and
Windows). A symbolic link is followed: its target is replaced, the link stays a link.
A batch run writes through one `OutputWriter`: outputs that already hold the new
bytes stay untouched, and each folder is fsynced once at the end.
"""

from __future__ import annotations

import os
import shutil
import stat
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

from urdfinertia.errors import OutputError

_UMASK_LOCK = threading.Lock()
SYNC_THREADS = 8
"""Folders `OutputWriter.close` fsyncs at once."""


def replace_file(target: Path, data: bytes, *, durable: bool = True,
                 mode: int | None = None, sync_folder: bool = True) -> None:
    """The one temporary-file-and-rename dance: `target` holds `data` or is untouched.

    The temporary file `.<name>.*.tmp` sits in `target`'s folder (a rename never
    crosses file systems) and is removed on any failure, KeyboardInterrupt included.
    `durable`: fsync the data before the rename and the folder after it (outputs);
    cache files skip both, since a lost cache entry only costs a recomputation.
    `mode`: permission bits of the new file (None: `mkstemp`'s 0600).
    `sync_folder`: False leaves the folder's fsync to the caller (`OutputWriter`
    syncs each folder once, after all its files). Raises OSError.
    """
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            if durable:
                fh.flush()
                os.fsync(fh.fileno())
        if mode is not None:
            os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    if durable and sync_folder:
        _fsync_folder(target.parent)


def atomic_write_bytes(path: str | Path, data: bytes) -> Path:
    """Write `data` to `path` atomically and return the file actually written.

    An existing file keeps its permission bits; a new one gets `0o666 & ~umask` like
    any file the user creates (`mkstemp` alone would give 0600).
    """
    path = Path(path)
    target = _follow_links(path)
    try:
        _replace_keeping_mode(target, data, sync_folder=True)
    except OSError as exc:
        raise OutputError(f"cannot write: {exc.strerror or exc}", file=path) from None
    return target


def _replace_keeping_mode(target: Path, data: bytes, *, sync_folder: bool) -> None:
    mode = target.stat().st_mode & 0o7777 if target.exists() else 0o666 & ~_umask()
    replace_file(target, data, mode=mode, sync_folder=sync_folder)


@dataclass(frozen=True)
class Written:
    """Where `OutputWriter.write` put its bytes.

    Attributes
    ----------
    path : Path
        The file holding them (a symbolic link's final target).
    untouched : bool
        The file already held exactly these bytes and was left as it was (same inode, same
        modification time).
    """

    path: Path
    untouched: bool


class OutputWriter:
    """Writes many outputs of one run, each atomically (`replace_file`).

    Differences from calling `atomic_write_bytes` per file: a file that already holds
    exactly the new bytes is left untouched (a second run over the same output folder
    rewrites nothing, and tools watching modification times see no change), and each
    folder is fsynced once, by `close`, after all its files rather than after each.
    Every file's own data is still fsynced before its rename, so until `close`
    returns a crash can lose a rename (the old file stays whole), never leave a
    half-written file. Thread-safe: a run writes from several threads at once.
    """

    def __init__(self) -> None:
        self._folders: dict[Path, None] = {}
        self._lock = threading.Lock()
        self.untouched = 0

    def write(self, path: str | Path, data: bytes) -> Written:
        """Make the file at `path` hold `data`; raises `OutputError`."""
        path = Path(path)
        target = _follow_links(path)
        try:
            if _holds(target, data):
                with self._lock:
                    self.untouched += 1
                return Written(target, True)
            _replace_keeping_mode(target, data, sync_folder=False)
        except OSError as exc:
            raise OutputError(f"cannot write: {exc.strerror or exc}", file=path) from None
        with self._lock:
            self._folders[target.parent] = None
        return Written(target, False)

    def close(self) -> None:
        """Make every rename durable: fsync each folder written to, once (a few at once:
        each waits for the file system's journal, and waits that overlap are shared)."""
        with self._lock:
            folders, self._folders = list(self._folders), {}
        if len(folders) <= 1:
            for folder in folders:
                _fsync_folder(folder)
            return
        import concurrent.futures as cf

        with cf.ThreadPoolExecutor(min(len(folders), SYNC_THREADS),
                                   thread_name_prefix="urdfinertia-sync") as pool:
            list(pool.map(_fsync_folder, folders))

    def __enter__(self) -> OutputWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _holds(target: Path, data: bytes) -> bool:
    """`target` is a regular file whose bytes are exactly `data` (False if missing)."""
    try:
        with open(target, "rb") as fh:
            st = os.fstat(fh.fileno())
            if not stat.S_ISREG(st.st_mode) or st.st_size != len(data):
                return False
            return fh.read(len(data) + 1) == data
    except OSError:  # missing, unreadable: written (and any error reported) as new
        return False


def write_in_place(path: str | Path, data: bytes, backup_suffix: str = ".bak") -> Path:
    """Replace the file at `path` (its symlink target) keeping `<target><suffix>`.

    The backup is a complete copy of the file as it was, written atomically before the
    file itself is touched (an older backup of the same name is replaced). Returns the
    path actually written.
    """
    target = _follow_links(Path(path))
    backup = target.with_name(target.name + backup_suffix)
    tmp = None
    try:
        tmp_fd, tmp = tempfile.mkstemp(prefix=f".{backup.name}.", suffix=".tmp",
                                       dir=target.parent)
        os.close(tmp_fd)
        shutil.copy2(target, tmp)
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, backup)
        tmp = None
    except OSError as exc:
        raise OutputError(f"cannot write backup {backup}: {exc.strerror or exc}",
                          file=path) from None
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass
    return atomic_write_bytes(target, data)


def _follow_links(path: Path) -> Path:
    """The file a write to `path` must replace: the final target of a symlink chain."""
    return Path(os.path.realpath(path)) if path.is_symlink() else path


def _fsync_folder(folder: Path) -> None:
    """Make the rename itself durable (not every file system lets a folder be fsynced)."""
    try:
        dir_fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(dir_fd)
    except OSError:
        pass
    finally:
        os.close(dir_fd)


def _umask() -> int:
    """The process umask, read without changing it where the system allows (Linux)."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    with _UMASK_LOCK:  # elsewhere: set and restore (not atomic, hence the lock)
        mask = os.umask(0o022)
        os.umask(mask)
        return mask
