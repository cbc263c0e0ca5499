"""Mesh files to closed bodies to exact integrals: read -> repair -> solids.

Owns the size limits (:mod:`.limits`), the reader registry by file suffix (:mod:`.read`),
the repair of real-world meshes (:mod:`.repair`: weld, orient, split, cap holes, union
overlapping bodies) and the integration of repaired bodies (:mod:`.solids`). May import:
:mod:`urdfinertia.inertia`, the foundation modules (``errors``, ``timing``, ``hostile``),
numpy, scipy, trimesh, pycollada and manifold3d; never descriptions, links, caches or the
CLI.
"""
