"""Each mesh computed once: per run (`.library`) and across runs (`.store`).

Owns `MeshLibrary` (URI -> resolved file -> solids,
memoised per run), the persistent store of solids with its entry codec and its one lookup
protocol (`.store`), file-content digests (`.digests`) and the one versioning
rule of every cached result (`.version`: the package's source digest). May import:
`urdfinertia.mesh`, `urdfinertia.descriptions` (paths), `urdfinertia.inertia`
and the foundation modules; never links, analysis or the CLI.
"""
