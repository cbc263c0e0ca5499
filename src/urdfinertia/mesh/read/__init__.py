"""Mesh files to triangles: one reader per format behind :func:`.load.load_mesh`.

STL by this package's reader (:mod:`.stl`), OBJ by trimesh's own per-format loader
(:mod:`.obj`), COLLADA by a direct geometry reader that gives trimesh's arrays
(:mod:`.collada`, trimesh's loader for what it does not reproduce: :mod:`.dae`), the
rest through ``trimesh.load``; every file is size-checked and face-counted before a
parser runs.
"""
