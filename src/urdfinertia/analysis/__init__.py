"""Judging inertials: lint them (:mod:`.check`), compare them (:mod:`.compare`), explain
a link element by element (:mod:`.explain`). Each renders the links' verdicts that
:func:`urdfinertia.plan.fix.link_verdicts` computes, the ones ``fix`` carries out.
May import: :mod:`urdfinertia.plan` and everything below it; never rendering, batch runs
or the CLI.
"""
