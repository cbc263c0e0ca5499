"""Showing results: terminal tables (:mod:`.table`), JSON (:mod:`.results_json`), PNG
plots (:mod:`.compare_plot`, :mod:`.explain_plot`) and the offline HTML report with its
3-D scene (:mod:`.report`, :mod:`.scene`). May import: :mod:`urdfinertia.analysis` and
everything below it; never batch runs or the CLI.
"""
