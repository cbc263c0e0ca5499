"""urdfinertia: make the inertials of robot descriptions right.

The public API, imported on first use (`import urdfinertia` loads neither lxml nor trimesh
nor numpy):

```python
import urdfinertia

result = urdfinertia.fix("robot.urdf")           # the command line's defaults
print(result.changed, [(r.name, r.status, r.why) for r in result.links])
print(urdfinertia.check("robot.urdf").findings)  # geometry read, as the command line does
```

| name | what it is |
|---|---|
| `check` | lint a file -> `CheckResult` (findings and every link's verdict) |
| `fix` | fix a file (keyword options) -> `FixResult` (the patched bytes in it) |
| `compare` | the written inertials against the geometry or another file |
| `explain` | one link: what `fix` writes and its geometry element by element |
| `report` | the HTML report -> `Report` (`.html`, `.save(path)`) |
| `write_back` | write a fixed xacro robot's values into its sources |
| `FixResult` | what `fix` returns: the verdicts, the output, `.save(path)` |
| `LinkResult` | one link's verdict: findings, action, reason, values before and after |
| `Status`, `Action` | what happened to a link, what the policy decided (string Enums) |
| `CheckResult` | what `check` returns |
| `Finding` | one finding, with its rule |
| `MassProperties` | the frozen value type: mass, CoM, inertia about the CoM in one frame |
| `combine` | the sum of bodies about their common CoM (Huygens-Steiner) |
| `read_description` | a description file -> (robot model, original bytes), any format |
| `FixOptions` | what to compute from (geometry, mass policy, density, spec ...) |
| `fix_file` | recompute a file's inertials -> `FixResult` |
| `fix_robot` | the same for a robot model already read |
| `check_robot` | lint a robot already read -> `CheckResult` |
| `load_spec` | read a decomposition spec (TOML) |
| `repair_tensor` | the minimal lift that makes an invalid tensor valid |
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.2.0"

_API = {
    "MassProperties": "urdfinertia.inertia.massprops",
    "combine": "urdfinertia.inertia.massprops",
    "repair_tensor": "urdfinertia.inertia.tensor_repair",
    "read_description": "urdfinertia.descriptions.formats",
    "FixOptions": "urdfinertia.body.options",
    "FixResult": "urdfinertia.plan.results",
    "fix_file": "urdfinertia.plan.fix",
    "fix_robot": "urdfinertia.plan.fix",
    "load_spec": "urdfinertia.body.spec",
    "check_robot": "urdfinertia.analysis.check",
    "CheckResult": "urdfinertia.analysis.check",
    "Finding": "urdfinertia.findings",
    "LinkResult": "urdfinertia.plan.results",
    "Status": "urdfinertia.plan.results",
    "Action": "urdfinertia.plan.results",
    "check": "urdfinertia.api",
    "fix": "urdfinertia.api",
    "compare": "urdfinertia.api",
    "explain": "urdfinertia.api",
    "report": "urdfinertia.api",
    "Report": "urdfinertia.api",
    "write_back": "urdfinertia.plan.save",
}
__all__ = sorted(_API)


def __getattr__(name: str) -> Any:
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'urdfinertia' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
