"""What can be known of a link without CAD: its robot's kind, its size, its place in the chain.

Everything here is read from the robot model (links, joints, names) and from the geometry
the tool integrates (its volume and box); nothing is fitted.
`robot_features` is
computed once per robot, `link_features` once per link.

How the robot's kind is inferred (`robot_kind`), first
rule that holds:

1. propellers, rotor-craft words (quadrotor, drone, flying...) or three rotors on the root
   link make it "aerial"; a thruster or hull "marine";
2. legs (the first links of chains named hip, thigh, knee, calf, shin, ankle, foot,
   leg...): fewer than four with arms, a torso or a head, "humanoid"; four or more,
   "quadruped"; otherwise a "humanoid" (a biped) too;
3. without a serial chain of four or more revolute joints (fingers' joints not counted):
   fingers (finger, thumb, palm, knuckle, phalanx...) on at least five moving joints and
   half of them, or three branches of two revolute joints or more from one link on a
   robot within `HAND_SIZE`, make a "hand"; a gripper's
   words (gripper, jaw, claw)
   or fingers a "gripper";
4. wheels on a robot without a serial chain of four or more revolute joints:
   "mobile base";
5. such a chain: an "industrial arm" when a maker's industrial series is named (KUKA KR,
   ABB IRB, Fanuc, Yaskawa Motoman, Staubli...), else a "cobot";
6. otherwise "other".
"""

from __future__ import annotations

import re
from collections import deque
from dataclasses import dataclass

import numpy as np

from urdfinertia.descriptions.model import Joint, Robot

#: The kinds of robot, as the data file and the docs name them.
ROBOT_KINDS = ("industrial arm", "cobot", "humanoid", "quadruped", "hand", "gripper",
               "mobile base", "aerial", "marine", "other")
#: m: a robot of three or more jointed branches from one link within this size is a hand
HAND_SIZE = 0.4
#: The kinds of link (where on the robot the part is).
PART_KINDS = ("base", "arm", "leg", "finger", "wheel", "head", "torso", "end", "other")
#: Material hints in a link's name: words for dense and for light parts.
MATERIAL_HINTS = ("dense", "light")

_WORDS: dict[str, tuple[str, ...]] = {
    "aerial": ("propeller", "quadrotor", "quadcopter", "hexacopter", "octocopter",
               "multirotor", "drone", "uav", "flying"),
    "marine": ("thruster", "hull", "rov", "auv", "boat", "vessel", "ship", "buoy"),
    "leg": ("hip", "thigh", "knee", "calf", "shin", "ankle", "foot", "feet", "leg", "tibia",
            "femur", "toe", "haa", "hfe", "kfe", "shank"),
    "arm": ("shoulder", "elbow", "wrist", "forearm", "upperarm", "arm", "humerus",
            "bicep", "clavicle"),
    "torso": ("torso", "pelvis", "waist", "chest", "trunk", "abdomen", "spine", "body"),
    "head": ("head", "neck", "camera", "eye", "skull"),
    "finger": ("finger", "thumb", "palm", "knuckle", "phalanx", "index", "middle", "ring",
               "pinky", "little", "distal", "proximal", "medial", "fingertip", "tip", "ff",
               "mf", "rf", "lf", "th", "mcp", "pip", "dip", "ffj", "mfj", "rfj", "lfj", "thj"),
    "gripper": ("gripper", "jaw", "claw", "pinch", "grasp", "robotiq", "hande", "pad"),
    "wheel": ("wheel", "caster", "castor", "tire", "tyre"),
    "base": ("base", "world", "root", "mount", "pedestal", "chassis", "platform"),
}
#: Makers' industrial series (lower-case, searched in the robot's and links' names).
_INDUSTRIAL = re.compile(r"(?<![a-z])kr\d|irb|fanuc|lrmate|lr_mate|motoman|yaskawa|staubli|"
                         r"stäubli|comau|kawasaki|nachi|denso|epson|(?<![a-z])crb(?![a-z])|"
                         r"(?<![a-z])m\d{2,}i[abcd]")
_HINTS = {"dense": ("motor", "servo", "actuator", "battery", "steel", "stator", "gear",
                    "drive", "brass", "lead", "weight"),
          "light": ("foam", "plastic", "pla", "abs", "cover", "shell", "carbon", "fairing",
                    "skin", "cap", "lid", "printed")}
_SPLIT = re.compile(r"[^a-z]+|(?<=[a-z])(?=\d)")


def words(name: str) -> set[str]:
    """The lower-case words of a name: split at anything not a letter and at camelCase
    ("rh_FFKnuckle2": rh, ff, knuckle)."""
    spaced = re.sub(r"(?<=[a-z])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", " ", name)
    return {w for w in _SPLIT.split(spaced.lower()) if w}


def _has(name: str, group: str) -> bool:
    """Whether a word of the group is in the name: a word of five letters or more may be
    part of a longer one ("ffknuckle"), a shorter one must stand alone ("arm", "hip")."""
    for w in words(name):
        for key in _WORDS[group]:
            if w == key or (len(key) >= 5 and key in w):
                return True
    return False


@dataclass(frozen=True)
class RobotFeatures:
    """What is known of a robot as a whole.

    kind : one of `ROBOT_KINDS`; why : the rule that gave
        it, in words.
    depth : per link, the number of moving joints between the root and the link.
    below : per link, the share of the robot's links in its subtree (the link excluded).
    joints : per link, the moving joints at the link (its parent joint and its children).
    extent : the largest distance of a link frame from the root at the zero
        configuration, m (the robot's size from its joints alone).
    """

    kind: str
    why: str
    depth: dict[str, int]
    below: dict[str, float]
    joints: dict[str, int]
    extent: float
    max_depth: int


@dataclass(frozen=True)
class LinkFeatures:
    """What is known of one link without CAD (the inputs of `model`).

    robot_kind, part : `ROBOT_KINDS`,
        `PART_KINDS`.
    geometry : "primitive", "hull" or "mesh"; role : "collision", "visual" or "geom".
    volume : of the geometry the tool integrates, m^3; fill : that volume over its box's.
    diagonal : the box's diagonal, m.
    depth_share : moving joints from the root over the robot's deepest chain (0 at the
        root, 1 at the deepest link); below : share of the robot's links below it.
    joints : moving joints at the link; extent : the robot's size, m.
    hints : "dense", "light" or "" (a material hint in the link's name).
    excess : the volume over the smallest of the link's geometries (1 when it is the
        smallest or the only one): collision stand-ins around a visual mesh, or an MJCF
        body whose counted geoms hold both, make it larger than 1.
    """

    robot_kind: str
    part: str
    geometry: str
    role: str
    volume: float
    fill: float
    diagonal: float
    depth_share: float
    below: float
    joints: int
    extent: float
    hints: str = ""
    excess: float = 1.0


def _children(robot: Robot) -> dict[str, list[Joint]]:
    names = {lk.name for lk in robot.links}
    out: dict[str, list[Joint]] = {n: [] for n in names}
    for j in robot.joints:
        if j.parent in names and j.child in names and j.child != j.parent:
            out[j.parent].append(j)
    return out


def _chain_revolute(children: dict[str, list[Joint]], roots: list[str]) -> int:
    """The most revolute joints on one path from a root, fingers' joints not counted (an
    arm's serial chain; a hand's fingers are not one)."""
    best = 0
    queue = deque((r, 0) for r in roots)
    seen: set[str] = set()
    while queue:
        name, n = queue.popleft()
        if name in seen:
            continue
        seen.add(name)
        best = max(best, n)
        for j in children.get(name, ()):
            arm = j.type in ("revolute", "continuous") and not (
                _has(j.name, "finger") or _has(j.child, "finger"))
            queue.append((j.child, n + arm))
    return best


def _fingers_from_one_link(children: dict[str, list[Joint]]) -> int:
    """The most branches of two or more revolute joints each that leave one link."""
    best = 0
    for joints in children.values():
        n = sum(_chain_revolute(children, [j.child]) + (j.type in ("revolute", "continuous"))
                >= 2 for j in joints)
        best = max(best, n)
    return best


def _extent(robot: Robot) -> float:
    """The largest distance of a link frame from the root at the zero configuration, m."""
    from urdfinertia.descriptions.kinematics import zero_configuration_poses

    poses, _ = zero_configuration_poses(robot)
    return max((float(np.linalg.norm(p[:3, 3])) for p in poses.values()), default=0.0)


def robot_kind(robot: Robot) -> tuple[str, str]:
    """The robot's kind (`ROBOT_KINDS`) and the rule that
    gave it (module doc)."""
    names = [robot.name] + [lk.name for lk in robot.links] + [j.name for j in robot.joints]
    moving = [j for j in robot.joints if j.type != "fixed"]
    count = {g: sum(_has(n, g) for n in names) for g in _WORDS}
    children = _children(robot)
    has_parent = {j.child for j in robot.joints}
    roots = [lk.name for lk in robot.links if lk.name not in has_parent] or \
        [lk.name for lk in robot.links[:1]]
    chain = _chain_revolute(children, roots)
    rotors = sum(1 for r in roots for j in children.get(r, ())
                 if words(j.child) & {"rotor", "prop", "propeller"})
    if count["aerial"] or rotors >= 3:
        return "aerial", "propellers, rotors on the base or rotor-craft words"
    if count["marine"]:
        return "marine", "thruster or hull words in the names"
    legs = _legs(robot)
    if legs and (count["arm"] or count["torso"] or count["head"]) and legs < 4:
        return "humanoid", f"{legs} legs with arms, a torso or a head"
    if legs >= 4:
        return "quadruped", f"{legs} legs"
    if legs:
        return "humanoid", f"{legs} legs"
    fingers = sum(_has(j.name, "finger") or _has(j.child, "finger") for j in moving)
    if chain < 4 and moving and fingers >= max(5, len(moving) / 2):
        return "hand", f"fingers on {fingers} of {len(moving)} moving joints, and no arm"
    branches = _fingers_from_one_link(children)
    if branches >= 3 and _extent(robot) < HAND_SIZE:
        return "hand", f"{branches} jointed branches from one link, within {HAND_SIZE} m"
    if chain < 4 and (count["gripper"] or fingers):
        return "gripper", "gripper words or fingers, and no arm"
    if count["wheel"] and chain < 4:
        return "mobile base", "wheels and no arm"
    if chain >= 4:
        text = " ".join(names).lower()
        if _INDUSTRIAL.search(text):
            return "industrial arm", f"a chain of {chain} revolute joints; an industrial series"
        return "cobot", f"a chain of {chain} revolute joints"
    return "other", "no rule holds"


def _legs(robot: Robot) -> int:
    """How many legs: links named as a leg with no leg-named link above them (each leg's
    first link; a leg's loops and unnamed links in between do not make new legs)."""
    parent = {j.child: j.parent for j in robot.joints if j.child != j.parent}
    n = 0
    for lk in robot.links:
        if not _has(lk.name, "leg"):
            continue
        up, seen = parent.get(lk.name), {lk.name}
        while up is not None and up not in seen and not _has(up, "leg"):
            seen.add(up)
            up = parent.get(up)
        n += up is None or up in seen
    return n


def robot_features(robot: Robot) -> RobotFeatures:
    """The robot-level features (computed once per robot)."""
    kind, why = robot_kind(robot)
    children = _children(robot)
    has_parent = {j.child for j in robot.joints if j.child in children and j.parent in children}
    roots = [lk.name for lk in robot.links if lk.name not in has_parent]
    depth: dict[str, int] = {}
    queue = deque((r, 0) for r in roots)
    while queue:
        name, d = queue.popleft()
        if name in depth:
            continue
        depth[name] = d
        for j in children[name]:
            queue.append((j.child, d + (j.type != "fixed")))
    for lk in robot.links:
        depth.setdefault(lk.name, 0)  # a link no root reaches (a loop): taken as a root
    below = {}
    total = len(robot.links)
    for lk in robot.links:
        below[lk.name] = (_subtree(lk.name, children) - 1) / max(total - 1, 1)
    joints = {lk.name: 0 for lk in robot.links}
    for j in robot.joints:
        if j.type == "fixed":
            continue
        for end in (j.parent, j.child):
            if end in joints:
                joints[end] += 1
    return RobotFeatures(kind, why, depth, below, joints, _extent(robot),
                         max(depth.values(), default=0))


def _subtree(name: str, children: dict[str, list[Joint]]) -> int:
    seen = {name}
    stack = [name]
    while stack:
        for j in children[stack.pop()]:
            if j.child not in seen:
                seen.add(j.child)
                stack.append(j.child)
    return len(seen)


def part_kind(link: str, robot: RobotFeatures) -> str:
    """Where on the robot the link is (`PART_KINDS`): from
    its name, else "base" at
    the root and "end" at a leaf."""
    w = words(link)
    for group in ("finger", "wheel", "leg", "arm", "head", "torso", "base"):
        if w & set(_WORDS[group]):
            return group
    if robot.depth.get(link, 0) == 0:
        return "base"
    if robot.joints.get(link, 0) <= 1:
        return "end"
    return "other"


def hints(*names: str) -> str:
    """"dense", "light" or "": a material hint in any of the names (dense wins)."""
    found = set().union(*(words(n) for n in names)) if names else set()
    for hint in MATERIAL_HINTS:
        if found & set(_HINTS[hint]):
            return hint
    return ""


def link_features(link: str, robot: RobotFeatures, *, volume: float,
                  box: tuple[np.ndarray, np.ndarray] | None, geometry: str, role: str,
                  others: tuple[float, ...] = ()) -> LinkFeatures:
    """The features of one link.

    Parameters
    ----------
    link : the link's name.
    robot : `robot_features` of its robot.
    volume : of the geometry the tool integrates, m^3 (positive).
    box : (min, max) corners of that geometry's box in the link frame, m; None when not
        known (the fill is then taken as 0.5).
    geometry, role : the geometry's kind and role (`urdfinertia.body.geometry_choice`).
    others : the volumes of the link's other geometries (candidate sets), m^3.
    """
    if not volume > 0:
        raise ValueError(f"volume must be positive, got {volume!r}")
    if box is not None:
        size = np.maximum(np.asarray(box[1], float) - np.asarray(box[0], float), 0.0)
        diagonal = float(np.linalg.norm(size))
        box_volume = float(np.prod(size))
        fill = min(volume / box_volume, 1.0) if box_volume > 0 else 1.0
    else:
        diagonal = float((6.0 * volume) ** (1 / 3) * np.sqrt(3))
        fill = 0.5
    share = robot.depth.get(link, 0) / robot.max_depth if robot.max_depth else 0.0
    smallest = min([volume, *(v for v in others if v > 0)])
    return LinkFeatures(robot.kind, part_kind(link, robot), geometry, role, float(volume),
                        float(fill), diagonal, float(share), float(robot.below.get(link, 0.0)),
                        int(robot.joints.get(link, 0)), float(robot.extent),
                        hints(link), float(volume / smallest))


@dataclass(frozen=True)
class JointAxis:
    """A moving joint at a link, in that link's frame.

    name : the joint's name; end : "parent" (the link is the joint's child) or "child"
    (the joint carries one of the link's children); point : (3,) a point of the axis, m;
    direction : (3,) its unit direction (a prismatic joint's motion direction).
    """

    name: str
    end: str
    point: tuple[float, float, float]
    direction: tuple[float, float, float]


def joint_axes(robot: Robot, link: str) -> tuple[JointAxis, ...]:
    """The moving joints at ``link``: its parent joint first, then its children's, each
    expressed in the link's frame (a joint without a readable axis is left out)."""
    out: list[JointAxis] = []
    for j in robot.joints:
        if j.type == "fixed" or link not in (j.parent, j.child) or j.parent == j.child:
            continue
        axis = np.asarray(j.axis, dtype=np.float64)
        norm = float(np.linalg.norm(axis))
        if not (np.isfinite(norm) and norm > 0):
            continue
        point = np.asarray(j.axis_point, dtype=np.float64)
        if j.child == link:
            end, p, d = "parent", point, axis / norm
        else:
            pose = j.origin.matrix()
            end, p, d = "child", pose[:3, :3] @ point + pose[:3, 3], pose[:3, :3] @ axis / norm
        if np.all(np.isfinite(p)) and np.all(np.isfinite(d)):
            out.append(JointAxis(j.name, end, _t3(p), _t3(d)))
    out.sort(key=lambda a: a.end != "parent")
    return tuple(out)


def _t3(v: np.ndarray) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))
