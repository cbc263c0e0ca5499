"""Real-world meshes to closed, outward-oriented bodies (:func:`.pipeline.repair_mesh`).

Stages: the edge graph (:mod:`.graph`), boundary loops (:mod:`.loops`), hole capping
(:mod:`.holes`), winding numbers for containment (:mod:`.winding`) and boolean unions of
overlapping bodies (:mod:`.union`).
"""
