"""Mesh files to closed bodies to exact integrals: read -> repair -> solids.

Owns the size limits (`.limits`), the reader registry by file suffix (`.read`),
the repair of real-world meshes (`.repair`: weld, orient, split, cap holes, union
overlapping bodies) and the integration of repaired bodies (`.solids`). May import:
`urdfinertia.inertia`, the foundation modules (`errors`, `timing`, `hostile`),
numpy, scipy, trimesh, pycollada and manifold3d; never descriptions, links, caches or the
CLI.
"""
