"""Atomic file writes: a temporary file in the target's folder, fsync, rename.

A failed run leaves no half-written output and an existing file is replaced only on
success: the new bytes go to a temporary file next to the target, are flushed to disk,
and the temporary file is renamed over the target (``os.replace``, atomic on POSIX and
Windows). A symbolic link is followed: its target is replaced, the link stays a link.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import threading
from pathlib import Path

from urdfinertia.errors import OutputError

_UMASK_LOCK = threading.Lock()


def atomic_write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically and return the file actually written.

    An existing file keeps its permission bits; a new one gets ``0o666 & ~umask`` like
    any file the user creates (``mkstemp`` alone would give 0600).
    """
    path = Path(path)
    target = _follow_links(path)
    folder = target.parent
    try:
        mode = target.stat().st_mode & 0o7777 if target.exists() else 0o666 & ~_umask()
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise OutputError(f"cannot write: {exc.strerror or exc}", file=path) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException as exc:  # also KeyboardInterrupt: never leave the temporary file
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            raise OutputError(f"cannot write: {exc.strerror or exc}", file=path) from None
        raise
    _fsync_folder(folder)
    return target


def write_in_place(path: str | Path, data: bytes, backup_suffix: str = ".bak") -> Path:
    """Replace the file at ``path`` (its symlink target) keeping ``<target><suffix>``.

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
    """The file a write to ``path`` must replace: the final target of a symlink chain."""
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
