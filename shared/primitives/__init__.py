"""The ten movement primitives (paper Section II): matrices, joints, tasks, IK."""

from shared.primitives.catalog import (
    BY_NAME,
    FULL_GRASP,
    FULL_REACH,
    MOTION_PRIMITIVES,
    PRIMITIVES,
    get_primitive,
    turning_the_wrist,
)
from shared.primitives.matrix import ATTRIBUTES, NODES, matrix_from_mp_form, mp_form
from shared.primitives.primitive import IKMethod, Primitive, PrimitiveType, Task

__all__ = [
    "ATTRIBUTES",
    "BY_NAME",
    "FULL_GRASP",
    "FULL_REACH",
    "MOTION_PRIMITIVES",
    "NODES",
    "PRIMITIVES",
    "IKMethod",
    "Primitive",
    "PrimitiveType",
    "Task",
    "get_primitive",
    "matrix_from_mp_form",
    "mp_form",
    "turning_the_wrist",
]
