"""Resolve, read and integrate each mesh file once per run."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from .errors import MeshError
from .mesh_io import DEFAULT_MAX_FACES, load_mesh
from .paths import resolve_mesh_path
from .solids import MeshSolids, mesh_solids


class MeshLibrary:
    """Mesh solids by URI, memoised by resolved file path for the life of the object.

    One library is shared by all links of a run, so a mesh referenced by several links
    (left and right legs, mirrored parts) is read and integrated once.
    """

    def __init__(
        self,
        package_dirs: Mapping[str, Path] | None = None,
        max_faces: int = DEFAULT_MAX_FACES,
    ) -> None:
        self.package_dirs = dict(package_dirs or {})
        self.max_faces = max_faces
        self._memo: dict[Path, MeshSolids] = {}

    def resolve(self, uri: str, urdf_dir: Path) -> Path:
        return resolve_mesh_path(uri, urdf_dir, self.package_dirs)

    def solids(self, path: Path) -> MeshSolids:
        """Unscaled solids of the mesh file at ``path``."""
        key = path.resolve()
        found = self._memo.get(key)
        if found is None:
            try:
                found = mesh_solids(load_mesh(key, self.max_faces))
            except MeshError as exc:
                if exc.file is None:
                    exc.file = str(path)
                raise
            self._memo[key] = found
        return found
