"""urdfinertia: make the inertials of robot descriptions right.

The public API, imported on first use (``import urdfinertia`` loads neither lxml nor
trimesh nor numpy)::

    from urdfinertia import FixOptions, fix_file
    result = fix_file("robot.urdf", FixOptions())
    print(result.changed, [r.status for r in result.links])

=====================  ===================================================================
``MassProperties``     the frozen value type: mass, CoM, inertia about the CoM in one frame
``combine``            the sum of bodies about their common CoM (Huygens-Steiner)
``read_description``   a description file -> (robot model, original bytes), any format
``FixOptions``         what to compute from (geometry, mass policy, density, spec ...)
``fix_file``           recompute a file's inertials -> ``FixResult`` (patched bytes in it)
``fix_robot``          the same for a robot model already read
``check_robot``        lint a robot's inertials -> findings
``load_spec``          read a decomposition spec (TOML)
``repair_tensor``      the minimal lift that makes an invalid tensor valid
=====================  ===================================================================
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

_API = {
    "MassProperties": "urdfinertia.inertia.massprops",
    "combine": "urdfinertia.inertia.massprops",
    "repair_tensor": "urdfinertia.inertia.tensor_repair",
    "read_description": "urdfinertia.descriptions.formats",
    "FixOptions": "urdfinertia.link.options",
    "FixResult": "urdfinertia.link.results",
    "fix_file": "urdfinertia.link.fix",
    "fix_robot": "urdfinertia.link.fix",
    "load_spec": "urdfinertia.link.spec",
    "check_robot": "urdfinertia.analysis.check",
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
