"""Content digests of files, remembered by their stat signature (as git's index does).

Hashing every mesh of a large collection dominates a warm run. A file whose device, inode,
size, modification and change times (nanoseconds) are those recorded with its digest has
the same content: `ctime` cannot be set by programs, so rewriting a file changes it.
Files changed less than `RACY_SECONDS` before they were hashed are not remembered:
within one timestamp tick a rewrite of the same size could keep every stat field ("racy
git"). The memo is a JSON file in the cache folder; anything unexpected in it is ignored.
Each record carries a check digest of its file name, stat signature and content digest, so
a damaged memo (a flipped digit, records permuted between files) can never map a file to
another file's content: a record that does not check is hashed again.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import time
from pathlib import Path

from urdfinertia.atomic import replace_file

RACY_SECONDS = 2.0
"""Files modified this recently (seconds) are hashed every time."""
MAX_FILES = 200_000
"""Memo size bound (files); beyond it, new files are hashed but not remembered."""
MEMO_FORMAT = "urdfinertia-digests/2"


def content_digest(data: bytes) -> str:
    """The digest the cache keys bytes by (BLAKE2b, 160 bits).

    Parameters
    ----------
    data : bytes
        A file's contents.

    Returns
    -------
    str
        40 hex digits.
    """
    return hashlib.blake2b(data, digest_size=20).hexdigest()


def file_digest(path: str | Path, max_bytes: int) -> str | None:
    """`content_digest` of a regular file of at most `max_bytes`, read in chunks.

    None for anything else: a FIFO (whose opening would block) or a huge file is not read.
    """
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return None  # before opening: a FIFO's open would block
        # non-blocking, checked again on the open file: it may have been replaced meanwhile
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_BINARY", 0))
        with os.fdopen(fd, "rb") as fh:
            info = os.fstat(fd)
            if not stat.S_ISREG(info.st_mode) or info.st_size > max_bytes:
                return None
            h = hashlib.blake2b(digest_size=20)
            read = 0
            while read <= max_bytes and (chunk := fh.read(1 << 20)):
                h.update(chunk)
                read += len(chunk)
    except OSError:
        return None
    return None if read > max_bytes else h.hexdigest()


def _record_check(name: str, sig: list, digest: str) -> str:
    """The check digest of one memo record (binds the digest to its file and signature)."""
    text = json.dumps([MEMO_FORMAT, name, sig, digest])
    return hashlib.blake2b(text.encode("utf-8"), digest_size=10).hexdigest()


class FileDigests:
    """Digest memo backed by `path` (loaded lazily, written by `save`)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._memo: dict[str, list] | None = None
        self._dirty = False

    def _load(self) -> dict[str, list]:
        if self._memo is None:
            self._memo = {}
            try:
                doc = json.loads(self.path.read_text(encoding="utf-8"))
                if isinstance(doc, dict) and doc.get("format") == MEMO_FORMAT:
                    files = doc.get("files")
                    if isinstance(files, dict):
                        self._memo = files
            except (OSError, ValueError):
                pass
        return self._memo

    def digest(self, path: str | Path, max_bytes: int) -> str | None:
        """The content digest of `path`, from the memo when its stat signature matches."""
        try:
            info = os.stat(path)
        except OSError:
            return None
        if not stat.S_ISREG(info.st_mode) or info.st_size > max_bytes:
            return None
        sig = [info.st_dev, info.st_ino, info.st_size, info.st_mtime_ns, info.st_ctime_ns]
        memo = self._load()
        name = str(path)
        found = memo.get(name)
        if (isinstance(found, list) and len(found) == 7 and found[:5] == sig
                and isinstance(found[5], str)
                and found[6] == _record_check(name, sig, found[5])):
            return found[5]
        digest = file_digest(path, max_bytes)
        changed = max(info.st_mtime_ns, info.st_ctime_ns)
        if (digest is not None and time.time_ns() - changed > RACY_SECONDS * 1e9
                and (name in memo or len(memo) < MAX_FILES)):
            memo[name] = [*sig, digest, _record_check(name, sig, digest)]
            self._dirty = True
        return digest

    def save(self) -> None:
        """Write the memo atomically if it changed (failures only cost a re-hash)."""
        if not self._dirty or self._memo is None:
            return
        data = json.dumps({"format": MEMO_FORMAT, "files": self._memo}).encode()
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            replace_file(self.path, data, durable=False)
        except OSError:
            return
        self._dirty = False
