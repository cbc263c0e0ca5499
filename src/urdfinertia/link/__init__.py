"""One link at a time: options, parts, the link's masses and their assembly, the fix job.

Owns :class:`~urdfinertia.link.options.FixOptions`, the parts of a link
(:mod:`.parts`: **where a part's tensor is computed**, primitives by closed form, meshes by
exact integrals), user-declared parts and materials (:mod:`.spec`, :mod:`.materials`),
the assembly of parts into the link's mass properties (:mod:`.assemble`: masses,
cavities, pinned totals, Huygens-Steiner sum; the paper's eqs. 43-46), the judgement of a
written inertial (:mod:`.plausibility`, :mod:`.findings`) and the decision taken from it
(:mod:`.policy`), one link computed (:mod:`.compute`) and its decision carried out
(:mod:`.apply`), and the robot orchestrated (:mod:`.fix`: :func:`~.fix.link_verdicts`
gives every link's :class:`~.results.LinkResult`, the one verdict every command renders;
imports go fix -> apply -> compute, an import-linter contract), and the minimal repair
(:mod:`.repair_only`). May import:
:mod:`urdfinertia.cache`, :mod:`urdfinertia.mesh`, :mod:`urdfinertia.descriptions`,
:mod:`urdfinertia.inertia` and the foundation modules; parts reach meshes through a
small lookup protocol, not the cache class.
"""
