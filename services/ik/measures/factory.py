"""Which measure H a primitive or a baseline uses, built where its phase starts."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from services.ik.kernel.chain import ChainState
from services.ik.measures.base import Measure, NoMeasure
from services.ik.measures.elbow_travel import ElbowTravel
from services.ik.measures.grasp import GraspBlend
from services.ik.measures.ntpe import WristDiscomfortEnergy
from services.ik.measures.params import MeasureParams
from services.ik.measures.swivel_goal import SwivelGoal
from services.ik.measures.tpe import TotalPotentialEnergy
from shared.messages.method import Method
from shared.primitives import IKMethod, Primitive

if TYPE_CHECKING:
    import numpy as np

#: Builds a measure from the posture where its phase of the movement starts.
MeasureFactory = Callable[[ChainState], Measure]


def ntpe(params: MeasureParams) -> WristDiscomfortEnergy:
    """NTPE (eq. 19) with ``params``'s coefficients."""
    return WristDiscomfortEnergy(
        TotalPotentialEnergy(params.mu), params.omega, params.wrist_centre
    )


def for_primitive(
    primitive: Primitive,
    goal: Sequence[float] | np.ndarray,
    params: MeasureParams,
    swivel: float | None = None,
) -> MeasureFactory:
    """The primitive's measure (SPEC table), from the posture where it starts.

    Args:
        primitive: The primitive.
        goal: Where the movement ends, wrist [m], 3 values: H_G's target.
        params: Measure coefficients.
        swivel: Swivel goal for the function primitive S_R E_P W_R [rad].
    """
    if primitive.ik is IKMethod.GPM_TPE:
        return lambda st: TotalPotentialEnergy(params.mu)
    if primitive.ik is IKMethod.GPM_GRASP:
        return lambda st: GraspBlend(
            ElbowTravel(st.origins[2]),
            ntpe(params),
            goal,
            math.dist(goal, st.origins[4]),
            params.k1,
            params.k2,
        )
    if primitive.ik is IKMethod.GPM_NULL and swivel is not None:
        return lambda st: SwivelGoal(swivel, params.swivel_weight)
    if primitive.ik.geometric:
        return lambda st: NoMeasure()
    return lambda st: ntpe(params)


def for_baseline(method: Method, params: MeasureParams) -> MeasureFactory:
    """least-norm: no measure; single: NTPE for the whole movement."""
    if method is Method.LEAST_NORM:
        return lambda st: NoMeasure()
    return lambda st: ntpe(params)
