"""engines: load a description in the simulators users run it in, and step it passively.

`check --engines mujoco,pinocchio,pybullet` and `fix --engines`: each engine runs in a
child process (`.probe`, the only module importing an engine) with a timeout, because
engines can crash or hang on bad inertia. `.prepare` writes the copy an engine can
load (meshes resolved, converted for MuJoCo); `.run` turns refusals, NaN, instability
warnings and runaway joint speeds into [`Finding`][urdfinertia.analysis.check.Finding];
`.silent` reports what engines do to inertials without refusing.

Layer: just above analysis (it makes analysis findings), below render and cli; it may
import descriptions, mesh, analysis and the foundation modules.
"""

from urdfinertia.engines.run import ENGINES, EngineCheck, Outcome, parse_engines

__all__ = ["ENGINES", "EngineCheck", "Outcome", "parse_engines"]
