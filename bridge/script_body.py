"""The body check the exported scripts carry: their move to the start keeps clear.

``play.py`` and the behavior's start box move the arm from wherever it is
when they run to the trajectory's start, without armplan (``bridge.
script_approach``). A straight move in joint space between two postures
clear of NAO's body can cross it (the bridge refuses such an approach:
``bridge.body_clearance``), so the scripts carry their own copy of the
body model (``shared.robot.body``) and of the arm's chain, in plain Python
2 and 3: :func:`body_source` is ``check_clear(names, keys, times)``, which
raises RuntimeError, before anything is sent, naming the first key that
brings an arm part within the margin of a body part.

The other arm is not in the exported plan (a plan knows it only if its
request gave ``other_arm``), so the scripts also carry that arm's chain:
``other_arm_parts(q)`` makes its capsules from the angles the robot
measures when the script runs, and ``check_clear(..., others=...)`` keeps
clear of them as of the body (``OTHER_ARM_ADVICE`` says what to do when
the plan does not). ``play.py`` checks its trajectory and its move to the
start so; the start box its move to the start and the timeline's keys,
before the timeline starts.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from shared.robot import Side, load_arm
from shared.robot.arm_model import ArmModel
from shared.robot.body import ARM_PARTS, BODY, MARGIN
from shared.robot.fk_many import AXES

_SOURCE = '''

ARM_SIDE = {side!r}
ARM_JOINTS = {joints}  # the arm's joints, in the chain's order
CHAIN = {chain}  # per joint: (axis 0/1/2 for x/y/z, offset in its parent [m])
POINTS = {points}  # key point: (joint it hangs on, 1-based; offset [m])
OTHER_SIDE = {other_side!r}  # the other arm, as the robot measures it
OTHER_JOINTS = {other_joints}
OTHER_CHAIN = {other_chain}
OTHER_POINTS = {other_points}
ARM_PARTS = {parts}  # (part, from point, to point, radius [m])
BODY = {body}  # (part, bottom [m], top [m], radius [m]) in the torso frame
BODY_MARGIN = {margin!r}  # least distance kept between surfaces [m]
OTHER_ARM_ADVICE = (
    "the plan did not keep clear of the other arm where the robot holds it: "
    "move that arm, or plan again saying where it is (armplan plan --other-arm)"
)


def _turn(axis, angle, vector):
    """``vector`` turned by ``angle`` [rad] about coordinate axis ``axis``."""
    import math

    c, s = math.cos(angle), math.sin(angle)
    first, second = (axis + 1) % 3, (axis + 2) % 3
    out = list(vector)
    out[first] = c * vector[first] - s * vector[second]
    out[second] = s * vector[first] + c * vector[second]
    return out


def _apply(frame, vector):
    """``vector`` in the torso frame, from the frame (axes, origin) it is in."""
    axes, origin = frame
    return [
        origin[i] + sum(axes[i][j] * vector[j] for j in range(3)) for i in range(3)
    ]


def _arm_points(q, chain=None, points=None):
    """The arm's key points [m] for angles ``q`` [rad] of ARM_JOINTS.

    ``chain`` and ``points``: another arm's (OTHER_CHAIN, OTHER_POINTS).
    """
    chain = CHAIN if chain is None else chain
    points = POINTS if points is None else points
    unit = [[float(i == j) for j in range(3)] for i in range(3)]
    frames = [(unit, [0.0, 0.0, 0.0])]
    for (axis, offset), angle in zip(chain, q):
        axes, origin = frames[-1]
        columns = [_turn(axis, angle, unit[j]) for j in range(3)]
        turned = [
            [sum(axes[i][k] * columns[j][k] for k in range(3)) for j in range(3)]
            for i in range(3)
        ]
        frames.append((turned, _apply((axes, origin), offset)))
    return dict(
        (name, _apply(frames[joint], offset))
        for name, (joint, offset) in points.items()
    )


def other_arm_parts(q):
    """The other arm at angles ``q`` [rad] of OTHER_JOINTS, as parts like BODY's.

    Its capsules are ARM_PARTS, named with its side (``left forearm``).
    """
    points = _arm_points(q, OTHER_CHAIN, OTHER_POINTS)
    return [
        ("%s %s" % (OTHER_SIDE, part), points[first], points[last], radius)
        for part, first, last, radius in ARM_PARTS
    ]


def _segment_distance(p0, p1, q0, q1):
    """Closest distance [m] between segments p0 p1 and q0 q1 (Ericson 5.1.9)."""
    d1 = [b - a for a, b in zip(p0, p1)]
    d2 = [b - a for a, b in zip(q0, q1)]
    r = [a - b for a, b in zip(p0, q0)]
    dot = lambda u, v: sum(x * y for x, y in zip(u, v))  # noqa: E731
    clamp = lambda x: min(1.0, max(0.0, x))  # noqa: E731
    a, e, f = dot(d1, d1), dot(d2, d2), dot(d2, r)
    if a <= 1e-18 and e <= 1e-18:
        s = t = 0.0
    elif a <= 1e-18:
        s, t = 0.0, clamp(f / e)
    else:
        c = dot(d1, r)
        if e <= 1e-18:
            s, t = clamp(-c / a), 0.0
        else:
            b = dot(d1, d2)
            denominator = a * e - b * b
            s = 0.0
            if denominator > 1e-18 * (a + e):
                s = clamp((b * f - c * e) / denominator)
            t = (b * s + f) / e
            if t < 0.0:
                s, t = clamp(-c / a), 0.0
            elif t > 1.0:
                s, t = clamp((b - c) / a), 1.0
    gap = [p + s * u - (q + t * v) for p, u, q, v in zip(p0, d1, q0, d2)]
    return dot(gap, gap) ** 0.5


def check_clear(
    names,
    keys,
    times,
    move="the move to the start",
    others=(),
    advice="move the arm away from the body first",
):
    """Raise RuntimeError at the first key that brings the arm near the body.

    ``keys``: one list per joint of ``names`` [rad]; ``times``: theirs [s];
    ``others``: more parts to keep clear of (``other_arm_parts``);
    ``advice``: what the error tells to do. Nothing is sent when it raises.
    """
    columns = [names.index(name) for name in ARM_JOINTS]
    parts = list(BODY) + list(others)
    for k in range(len(keys[columns[0]])):
        points = _arm_points([keys[j][k] for j in columns])
        worst = None
        for part, first, last, radius in ARM_PARTS:
            for body, bottom, top, body_radius in parts:
                gap = _segment_distance(points[first], points[last], bottom, top)
                gap -= radius + body_radius
                if worst is None or gap < worst[0]:
                    worst = (gap, part, body)
        if not worst[0] >= BODY_MARGIN:  # NaN: refused
            gap, part, body = worst
            if gap < 0:
                near = "%.1f mm into" % (-gap * 1000)
            else:
                near = "%.1f mm (less than the %.1f mm kept) from" % (
                    gap * 1000, BODY_MARGIN * 1000)
            raise RuntimeError(
                "%s would bring the %s %s %s NAO's %s at key %d (t = %.3f s); "
                "nothing of it was sent: %s"
                % (move, ARM_SIDE, part, near, body, k + 1, times[columns[0]][k],
                   advice)
            )
'''


def body_source(side: Side | str) -> str:
    """``check_clear`` and the data it needs, for the arm of ``side``.

    Raises:
        ValueError: the robot description turns a joint's frame in its
            parent (the scripts' chain keeps only offsets and axes).
    """
    arm = load_arm(side)
    other = load_arm(Side.LEFT if arm.side is Side.RIGHT else Side.RIGHT)
    joints, chain, points = _chain(arm)
    other_joints, other_chain, other_points = _chain(other)
    body = [(part.name, part.bottom, part.top, part.radius) for part in BODY]
    return _SOURCE.format(
        side=arm.side.value,
        joints=repr(joints),
        chain=repr(chain),
        points=repr(points),
        other_side=other.side.value,
        other_joints=repr(other_joints),
        other_chain=repr(other_chain),
        other_points=repr(other_points),
        parts=repr([tuple(part) for part in ARM_PARTS]),
        body=repr(body),
        margin=MARGIN,
    )


def _chain(arm: ArmModel) -> tuple[list[str], list[Any], dict[str, Any]]:
    """The arm's joint names, chain and key points, as the scripts hold them.

    Raises:
        ValueError: a joint's frame is turned in its parent.
    """
    model = arm.model
    chain = []
    for joint in range(1, model.njoints):
        placement = model.jointPlacements[joint]
        if not np.allclose(placement.rotation, np.eye(3)):
            raise ValueError(f"joint {model.names[joint]} is turned in its parent")
        axis = AXES[model.joints[joint].shortname()]
        chain.append((axis, tuple(float(v) for v in placement.translation)))
    points = {}
    for name, frame_id in arm.frame_ids.items():
        frame = model.frames[frame_id]
        offset = tuple(float(v) for v in frame.placement.translation)
        points[name] = (int(frame.parentJoint), offset)
    return [model.names[j] for j in range(1, model.njoints)], chain, points


__all__ = ["body_source"]
