"""Many files at once: inputs (:mod:`.inputs`), the run with each mesh computed once
(:mod:`.run`), worker pools and Dask (:mod:`.executors`) and whole-file results in the
cache (:mod:`.file_cache`). May import: everything but the CLI.
"""
