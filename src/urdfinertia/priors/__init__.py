"""Priors for what a description does not say: a link's mass and the structure of its tensor.

Owns the features of a link that can be known without CAD
(`features`: the robot's
kind, the part's size and place in the chain, its joints, material hints in names), the
terms of the density model (`urdfinertia.priors.terms`), the mass prior and the robot total with
their
calibrated bands (`model`), the structure prior of a tensor as plain
parts
(`structure`), the packaged data file they read
(`urdfinertia.priors.data`:
``urdfinertia/data/priors.json``, written by ``scripts/bench_priors.py``) and the fit that
writes it (`urdfinertia.priors.fit`, used by the benchmark and the tests). No fitted number lives in
the code. May import: [`urdfinertia.descriptions`][urdfinertia.descriptions],
[`urdfinertia.inertia`][urdfinertia.inertia], numpy
and the foundation modules; never links, analysis, rendering or the CLI (an import-linter
contract), so that ``fix`` can call it without a cycle.
"""
