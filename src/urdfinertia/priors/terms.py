"""The terms of the density model: what each link feature contributes, one column each.

The model (`model`) is linear in these terms on the log10 of the
effective density; the fit (`urdfinertia.priors.fit`) and the prediction both build
them here, so the data file's coefficient names and the code cannot drift apart.

- ``intercept``: 1;
- ``robot:<kind>``, ``part:<kind>``, ``geometry:<kind>``, ``role:<role>``, ``hint:<hint>``:
  1 for the link's own category, else 0 (a category the data file has no coefficient for
  contributes nothing: the link is predicted as the average one);
- ``log_volume``: log10 of the volume over one litre; ``log_fill``: log10 of the volume
  over its box's; ``log_extent``: log10 of the robot's size over one metre (at least
  `MIN_EXTENT`); ``log_excess``: log10 of the volume over the link's smallest
  geometry's (:attr:`~urdfinertia.priors.features.LinkFeatures.excess`);
- ``depth_share``, ``below``: 0..1; ``joints``: moving joints at the link, at most
  `MAX_JOINTS`.
"""

from __future__ import annotations

import math

from urdfinertia.priors.features import LinkFeatures

#: m: a robot smaller than this (a single part, joints at its origin) is taken as this big
MIN_EXTENT = 0.05
#: joints beyond this many at one link (a hand's palm) add nothing more
MAX_JOINTS = 4
#: the smallest fill used (a thin shell in a large box): the log stays finite
MIN_FILL = 1e-3
#: the numeric terms, in order
NUMERIC = ("log_volume", "log_fill", "log_extent", "log_excess", "depth_share", "below",
           "joints")
#: the categorical features and the prefix of their terms
CATEGORIES = (("robot", "robot_kind"), ("part", "part"), ("geometry", "geometry"),
              ("role", "role"), ("hint", "hints"))


def term_values(f: LinkFeatures) -> dict[str, float]:
    """Every term of ``f`` that is not zero, by name."""
    out = {"intercept": 1.0,
           "log_volume": math.log10(f.volume / 1e-3),
           "log_fill": math.log10(max(f.fill, MIN_FILL)),
           "log_extent": math.log10(max(f.extent, MIN_EXTENT)),
           "log_excess": math.log10(max(f.excess, 1.0)),
           "depth_share": f.depth_share,
           "below": f.below,
           "joints": float(min(f.joints, MAX_JOINTS))}
    for prefix, attribute in CATEGORIES:
        value = getattr(f, attribute)
        if value:
            out[f"{prefix}:{value}"] = 1.0
    return out
