"""Mesh files to triangles: one reader per format behind `.load.load_mesh`.

STL by this package's reader (`.stl`), OBJ by trimesh's own per-format loader
(`.obj`), COLLADA by a direct geometry reader that gives trimesh's arrays
(`.collada`, trimesh's loader for what it does not reproduce: `.dae`), the
rest through `trimesh.load`; every file is size-checked and face-counted before a
parser runs.
"""
