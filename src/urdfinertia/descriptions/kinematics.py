"""The joint tree, in one place: link poses at the zero configuration, which links move,
and which are welded together by fixed joints (`check`'s lumping, the report's poses).

Many simulators (Gazebo, MuJoCo's `fusestatic`, Pinocchio's reduced models) merge links
joined by fixed joints into one body, so what must be physical is often the merged body.
A link "moves" when it is the child of a joint that is not fixed.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from urdfinertia.descriptions.model import Joint, Robot


@dataclass(frozen=True, eq=False)
class FixedGroup:
    """Links welded to `root` by fixed joints.

    Attributes
    ----------
    root : str
        The link the others are welded to.
    members : tuple of str
        The link names, root first.
    poses : tuple of (4, 4) float
        The pose of each member's frame in the root's frame, in the same order.
    """

    root: str
    members: tuple[str, ...]
    poses: tuple[np.ndarray, ...]


class Kinematics:
    """Parent joints, moving links and fixed groups of a robot (tolerates broken trees)."""

    def __init__(self, robot: Robot) -> None:
        names = {link.name for link in robot.links}
        self.parent_joint: dict[str, Joint] = {}
        for joint in robot.joints:
            if joint.child in names and joint.parent in names:
                self.parent_joint.setdefault(joint.child, joint)
        self._group_root: dict[str, str] = {}
        self._pose_in_root: dict[str, np.ndarray] = {}
        for link in robot.links:
            self._walk_up(link.name)
        members: dict[str, list[str]] = {}
        for link in robot.links:
            members.setdefault(self._group_root[link.name], []).append(link.name)
        self.groups: dict[str, FixedGroup] = {}
        for root, names_ in members.items():
            ordered = [root] + [n for n in names_ if n != root]
            self.groups[root] = FixedGroup(root, tuple(ordered),
                                           tuple(self._pose_in_root[n] for n in ordered))

    def _walk_up(self, name: str) -> None:
        chain = []
        seen = set()
        cur = name
        while cur not in self._group_root:
            joint = self.parent_joint.get(cur)
            if joint is None or joint.type != "fixed" or cur in seen:
                self._group_root[cur] = cur
                self._pose_in_root[cur] = np.eye(4)
                break
            seen.add(cur)
            chain.append((cur, joint))
            cur = joint.parent
        for child, joint in reversed(chain):
            parent = joint.parent
            self._group_root[child] = self._group_root[parent]
            self._pose_in_root[child] = self._pose_in_root[parent] @ joint.origin.matrix()

    def moves(self, name: str) -> bool:
        """Whether link `name` is the child of a moving (not fixed) joint.

        Parameters
        ----------
        name : str
            A link.

        Returns
        -------
        bool
            False for the root and for links on fixed joints.
        """
        joint = self.parent_joint.get(name)
        return joint is not None and joint.type != "fixed"

    def group_of(self, name: str) -> FixedGroup:
        """The group of links welded to link `name` by fixed joints.

        Parameters
        ----------
        name : str
            A link.

        Returns
        -------
        FixedGroup
            Its group (a group of one for a link with no fixed joint).
        """
        return self.groups[self._group_root[name]]


def zero_configuration_poses(robot: Robot) -> tuple[dict[str, np.ndarray], tuple[str, ...]]:
    """(4, 4) pose of every link in the root frame with every joint at 0.

    Returns the poses and notes on anything odd (several roots, links no joint reaches,
    joints naming unknown links). Several roots all sit at the identity; so does a link
    that no chain from a root reaches (a kinematic loop).
    """
    names = [link.name for link in robot.links]
    known = set(names)
    notes: list[str] = []
    children: dict[str, list] = {name: [] for name in names}
    has_parent: set[str] = set()
    for joint in robot.joints:
        if joint.parent not in known or joint.child not in known:
            notes.append(f"joint '{joint.name}' names an unknown link: not drawn")
            continue
        children[joint.parent].append(joint)
        has_parent.add(joint.child)
    roots = [name for name in names if name not in has_parent]
    if len(roots) > 1:
        notes.append(f"{len(roots)} root links ({', '.join(roots[:5])}"
                     f"{', ...' if len(roots) > 5 else ''}): all drawn at the origin")
    poses: dict[str, np.ndarray] = {root: np.eye(4) for root in roots}
    queue = deque(roots)
    while queue:
        parent = queue.popleft()
        for joint in children[parent]:
            if joint.child in poses:
                continue
            poses[joint.child] = poses[parent] @ joint.origin.matrix()
            queue.append(joint.child)
    missing = [name for name in names if name not in poses]
    if missing:
        notes.append(f"{len(missing)} link(s) not reached from a root (kinematic loop?): "
                     "drawn at the origin")
        for name in missing:
            poses[name] = np.eye(4)
    return poses, tuple(notes)
