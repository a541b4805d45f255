"""The ten movement primitives of the paper's Table 1, as data.

Matrices are the paper's (Section II.C) with one correction: the paper prints
the matrix of S_R E_P W_PR as [0,0,0; 1,0,0; 0,1,1], identical to that of
S_R E_PR W_PR; its product a e j would read "S_R E_PR W_PR". We use
[0,1,0; 1,0,0; 0,0,1], whose product is the primitive's own name. The two
function primitives (FMP) have no printed matrix; theirs follow from their
names in the same way.

Active joints, task and IK method follow the SPEC's primitive table, with one
documented exception below. In human
terms ElbowYaw is the upper arm's rotation about its own axis, a shoulder
degree of freedom: S_R with the elbow passive in position (S_R W_P, S_R W_PR)
turns only ElbowYaw, which swings the wrist round the upper arm while the
elbow stays put (the paper's "alternate-generation" form, eq. 13); S_R with
E_P or E_PR turns all three shoulder joints.

NAO's ElbowYaw axis runs through the elbow, 15 mm beside the shoulder, so
ShoulderPitch, ShoulderRoll and ElbowYaw are not a spherical joint: with
ElbowRoll still, they cannot turn the arm about the shoulder-wrist line while
the wrist stays exactly put (they would move it by up to 7 mm per radian of
ElbowYaw). Two consequences, both keeping the paper's intent:

- S_R E_P W_P and S_R E_P W_PR (the shoulder swings an arm of fixed shape)
  control the wrist's position, as the other motion primitives: ElbowYaw
  changes the wrist's distance from the shoulder (by up to 10.5 mm, within
  ``ArmModel.distance_span_at``), so three joints meet three coordinates.
- S_R E_P W_R (function primitive: the wrist is held in place while the
  elbow swivels round it) also moves ElbowRoll, by the small amount that
  keeps the wrist exactly still on NAO. The SPEC's table lists it with the
  shoulder joints and WristYaw only; on NAO those cannot hold the wrist.
"""

from __future__ import annotations

from shared.errors import UnknownPrimitiveError
from shared.primitives.primitive import IKMethod, Primitive, PrimitiveType, Task

_MMP, _FMP = PrimitiveType.MMP, PrimitiveType.FMP

#: Table 1, in the paper's order.
PRIMITIVES: tuple[Primitive, ...] = (
    Primitive(
        ((0, 1, 1), (1, 0, 0), (0, 0, 0)),
        _MMP,
        (0, 1, 2),
        Task.POSITION,
        IKMethod.GPM_TPE,
    ),
    Primitive(
        ((0, 0, 1), (0, 1, 0), (0, 0, 0)),
        _MMP,
        (3,),
        Task.POSITION,
        IKMethod.ELBOW_TRIANGLE,
    ),
    Primitive(
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        _MMP,
        (0, 1, 2, 3),
        Task.POSITION,
        IKMethod.GPM_TPE,
    ),
    Primitive(
        ((0, 1, 0), (1, 0, 0), (0, 0, 1)),
        _MMP,
        (0, 1, 2, 4),
        Task.POSE,
        IKMethod.GPM_GRASP,
    ),
    Primitive(
        ((0, 0, 1), (1, 0, 0), (0, 0, 0)),
        _MMP,
        (2,),
        Task.POSITION,
        IKMethod.SHOULDER_ROTATION,
    ),
    Primitive(
        ((0, 0, 0), (1, 0, 0), (0, 0, 1)), _MMP, (2, 4), Task.POSE, IKMethod.GPM_GRASP
    ),
    Primitive(
        ((0, 0, 0), (0, 1, 0), (0, 0, 1)), _MMP, (3, 4), Task.POSE, IKMethod.GPM_GRASP
    ),
    Primitive(
        ((0, 0, 0), (1, 0, 0), (0, 1, 1)),
        _MMP,
        (0, 1, 2, 3, 4),
        Task.POSE,
        IKMethod.GPM_GRASP,
    ),
    Primitive(
        ((0, 1, 0), (1, 0, 1), (0, 0, 0)),
        _FMP,
        (0, 1, 2, 3, 4),  # ElbowRoll included: see the module docstring
        Task.HOLD,
        IKMethod.GPM_NULL,
    ),
    Primitive(
        ((0, 0, 0), (0, 0, 1), (0, 0, 0)), _FMP, (4,), Task.TURN, IKMethod.WRIST_TURN
    ),
)

#: The primitives by name.
BY_NAME: dict[str, Primitive] = {p.name: p for p in PRIMITIVES}

#: The eight motion primitives, the decision's candidates (eq. 10).
MOTION_PRIMITIVES: tuple[Primitive, ...] = tuple(
    p for p in PRIMITIVES if p.kind is _MMP
)

#: The reaching primitive with every position joint active (the default for a reach).
FULL_REACH = BY_NAME["S_R E_PR W_P"]
#: The grasping primitive with all five joints active (the default with an orientation).
FULL_GRASP = BY_NAME["S_R E_PR W_PR"]


def turning_the_wrist(primitive: Primitive) -> Primitive:
    """The primitive that moves as ``primitive`` does and also turns the wrist.

    Each position-only motion primitive (``... W_P``) has a counterpart with
    WristYaw active (``... W_PR``); a primitive that turns the wrist already
    is its own. Used where a palm direction is wanted: NAO meets it only with
    WristYaw.
    """
    if primitive.orients_wrist:
        return primitive
    return BY_NAME[primitive.name.replace("W_P", "W_PR")]


def get_primitive(name: str) -> Primitive:
    """The primitive called ``name`` (e.g. ``"S_R E_PR W_P"``; spacing is free).

    Raises:
        UnknownPrimitiveError: if no primitive has that name.
    """
    key = " ".join(str(name).replace(",", " ").split())
    try:
        return BY_NAME[key]
    except KeyError:
        raise UnknownPrimitiveError(str(name), list(BY_NAME)) from None
