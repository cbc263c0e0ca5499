"""The plan and its execution: what ``fix`` does with every link, decided once.

Last stage of a verdict (body -> judge -> plan). :mod:`.policy` decides every link from the
judgement, fallbacks included; :mod:`.apply` and :mod:`.compute` carry the decision out;
:mod:`.fix` orchestrates the robot (:func:`~.fix.link_verdicts` gives every link's
:class:`~.results.LinkResult`, the one verdict every command renders) and patches the
document; :mod:`.total_mass` meets target masses; :mod:`.save` writes the result;
:mod:`.edits` gives the text edits of undone slips; :mod:`.repair_only` is the minimal
repair alone.

May import: :mod:`urdfinertia.judge` and everything below it; never analysis, rendering,
batch runs or the CLI.
"""
