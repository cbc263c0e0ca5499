"""Atomic file writes: a temporary file in the target's folder, fsync, rename.

A failed run leaves no half-written output and an existing file is replaced only on
success. ``--in-place`` writes through a symbolic link to its target.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from .errors import OutputError


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically, keeping an existing file's permissions."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    try:
        mode = path.stat().st_mode & 0o7777 if path.exists() else None
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise OutputError(f"cannot write: {exc.strerror or exc}", file=path) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        if mode is not None:
            os.chmod(tmp, mode)
        os.replace(tmp, path)
    except OSError as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise OutputError(f"cannot write: {exc.strerror or exc}", file=path) from None
    try:
        dir_fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)
    except OSError:
        pass  # not every file system lets a folder be fsynced


def write_in_place(path: str | Path, data: bytes, backup_suffix: str = ".bak") -> Path:
    """Replace the file at ``path`` (its symlink target) keeping ``<target><suffix>``.

    Returns the path actually written.
    """
    target = Path(os.path.realpath(path))
    backup = target.with_name(target.name + backup_suffix)
    try:
        tmp_fd, tmp = tempfile.mkstemp(prefix=f".{backup.name}.", dir=target.parent)
        os.close(tmp_fd)
        shutil.copy2(target, tmp)
        os.replace(tmp, backup)
    except OSError as exc:
        raise OutputError(f"cannot write backup {backup}: {exc.strerror or exc}",
                          file=path) from None
    atomic_write_bytes(target, data)
    return target
