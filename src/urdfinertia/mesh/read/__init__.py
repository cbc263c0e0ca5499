"""Mesh files to triangles: one reader per format behind :func:`.load.load_mesh`.

STL by this package's reader (:mod:`.stl`), OBJ and COLLADA by trimesh's own per-format
loaders (:mod:`.obj`, :mod:`.dae`), the rest through ``trimesh.load``; every file is
size-checked and face-counted before a parser runs.
"""
