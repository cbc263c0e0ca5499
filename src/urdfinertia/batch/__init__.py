"""Many files at once: inputs (`.inputs`), the run with each mesh computed once
(`.run`), worker pools and Dask (`.executors`) and whole-file results in the
cache (`.file_cache`). May import: everything but the CLI.
"""
