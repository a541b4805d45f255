"""Which measure H a primitive or a baseline uses, built where its phase starts."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from services.ik.measures.base import Measure, NoMeasure
from services.ik.measures.elbow_travel import ElbowTravel
from services.ik.measures.grasp import GraspBlend
from services.ik.measures.ntpe import WristDiscomfortEnergy
from services.ik.measures.params import MeasureParams
from services.ik.measures.swivel_goal import SwivelGoal
from services.ik.measures.tpe import TotalPotentialEnergy
from shared.messages.method import Method
from shared.primitives import IKMethod, Primitive
from shared.robot.arm_model import Kinematics

#: Builds a measure from the posture where its phase of the movement starts.
MeasureFactory = Callable[[Kinematics], Measure]


def ntpe(params: MeasureParams) -> WristDiscomfortEnergy:
    """NTPE (eq. 19) with ``params``'s coefficients."""
    return WristDiscomfortEnergy(
        TotalPotentialEnergy(params.mu), params.omega, params.wrist_centre
    )


def for_primitive(
    primitive: Primitive,
    goal: np.ndarray,
    params: MeasureParams,
    swivel: float | None = None,
) -> MeasureFactory:
    """The primitive's measure (SPEC table), from the posture where it starts.

    Args:
        primitive: The primitive.
        goal: Where the movement ends, wrist [m], shape (3,): H_G's target.
        params: Measure coefficients.
        swivel: Swivel goal for the function primitive S_R E_P W_R [rad].
    """
    if primitive.ik is IKMethod.GPM_TPE:
        return lambda kin: TotalPotentialEnergy(params.mu)
    if primitive.ik is IKMethod.GPM_GRASP:
        return lambda kin: GraspBlend(
            ElbowTravel(kin.elbow),
            ntpe(params),
            goal,
            float(np.linalg.norm(goal - kin.wrist)),
            params.k1,
            params.k2,
        )
    if primitive.ik is IKMethod.GPM_NULL and swivel is not None:
        return lambda kin: SwivelGoal(swivel, params.swivel_weight)
    if primitive.ik.geometric:
        return lambda kin: NoMeasure()
    return lambda kin: ntpe(params)


def for_baseline(method: Method, params: MeasureParams) -> MeasureFactory:
    """least-norm: no measure; single: NTPE for the whole movement."""
    if method is Method.LEAST_NORM:
        return lambda kin: NoMeasure()
    return lambda kin: ntpe(params)
