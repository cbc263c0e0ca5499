"""Real-world meshes to closed, outward-oriented bodies (`.pipeline.repair_mesh`).

Stages: the edge graph (`.graph`), boundary loops (`.loops`), hole capping
(`.holes`), winding numbers for containment (`.winding`) and boolean unions of
overlapping bodies (`.union`).
"""
