"""The maths of mass properties: pure numpy, no files, no XML, no other subpackage.

Owns the frozen value type [`MassProperties`][urdfinertia.inertia.massprops.MassProperties] (mass,
CoM, inertia about the CoM in one frame; `rotated`, `translated`, `+`/`combine`),
rotations (URDF rpy = Rz Ry Rx, the paper's eqs. 15-17), the closed forms of primitives
(`.primitives`), exact polyhedral integrals of meshes (`.polyhedron`), the one
definition of a physically valid tensor and its tolerances (`.validity`) and the
minimal repair of an invalid one (`.tensor_repair`). May import: numpy only.
"""
