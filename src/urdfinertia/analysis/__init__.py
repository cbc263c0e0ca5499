"""Judging inertials: lint them (:mod:`.check`), compare them (:mod:`.compare`), explain
a link element by element (:mod:`.explain`), and the geometry bounds these use
(:mod:`.bounds`). May import: :mod:`urdfinertia.link` and everything below it; never
rendering, batch runs or the CLI.
"""
