"""The judgement: every rule of the registry (:mod:`urdfinertia.rules`) applied to the
robot's evidence, with the whole robot as evidence.

Second stage of a verdict (body -> judge -> plan). Pure over the body model: it reads no
file and changes nothing. Owns the rules on the written values and against the geometry
(:mod:`.plausibility`), the slip search of one link (:mod:`.slips`), copies and mirror twins
(:mod:`.twins`) and realizability inside the geometry (:mod:`.realizability`).

May import: :mod:`urdfinertia.body` and everything below it; never the plan, analysis,
rendering or the CLI.
"""
