"""Each mesh computed once: per run (:mod:`.library`) and across runs (:mod:`.store`).

Owns :class:`~urdfinertia.cache.library.MeshLibrary` (URI -> resolved file -> solids,
memoised per run), the persistent store of solids with its entry codec and its one lookup
protocol (:mod:`.store`), file-content digests (:mod:`.digests`) and the one versioning
rule of every cached result (:mod:`.version`: the package's source digest). May import:
:mod:`urdfinertia.mesh`, :mod:`urdfinertia.descriptions` (paths), :mod:`urdfinertia.inertia`
and the foundation modules; never links, analysis or the CLI.
"""
