"""The one versioning rule of every cached result: the package's version and source.

A cache entry (a mesh's solids, a whole file's result) is keyed by what it was computed
from *and* by `code_digest`, a digest of every module of this package. Any edit to
the code, released or not, therefore invalidates every entry: no entry outlives the code
that wrote it, and there is no hand-bumped algorithm version to forget.
"""

from __future__ import annotations

import functools
import hashlib
from pathlib import Path

from urdfinertia import __version__

_PACKAGE = Path(__file__).resolve().parents[1]


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """Digest of the package version, of every `.py` file under the package and of its
    data files (the priors: their numbers change what `fix` derives).

    Reads about 0.5 MB of source once per process (a few milliseconds), instead of
    importing or parsing anything.
    """
    h = hashlib.blake2b(digest_size=16)
    h.update(__version__.encode() + b"\0")
    data = [p for p in (_PACKAGE / "data").rglob("*") if p.is_file()]
    for path in sorted([*_PACKAGE.rglob("*.py"), *data]):
        h.update(path.relative_to(_PACKAGE).as_posix().encode() + b"\0"
                 + path.read_bytes() + b"\0")
    return h.hexdigest()
