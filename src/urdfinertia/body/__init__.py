"""The body model: what a link's description says and what its geometry is.

First stage of a verdict (body -> judge -> plan). Owns the user's options
(:mod:`.options`), the parts of a link (:mod:`.parts`: **where a part's tensor is
computed**, primitives by closed form, meshes by exact integrals), user-declared parts and
materials (:mod:`.spec`, :mod:`.materials`, shells in :mod:`.shell_voxels`), the assembly
of parts into mass properties (:mod:`.assemble`: the paper's eqs. 43-46, Huygens-Steiner),
mass sources (:mod:`.mass`), the geometry's box and hull (:mod:`.bounds`, :mod:`.hull`),
the candidate geometries of a link and the choice among them (:mod:`.geometry_choice`),
the calibrated error of a homogeneous body (:mod:`.errorbar`) and the evidence each link
brings to its judgement (:mod:`.evidence`). Nothing here judges a written value.

May import: :mod:`urdfinertia.cache`, :mod:`urdfinertia.mesh`,
:mod:`urdfinertia.descriptions`, :mod:`urdfinertia.inertia` and the foundation modules;
parts reach meshes through a small lookup protocol, not the cache class.
"""
