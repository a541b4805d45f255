"""Geometry of an arm posture shared by IK, decision and demonstrations."""

from shared.geometry.palm import palm_normal, roll_error
from shared.geometry.swivel import SWIVEL_DOWN, swivel_angle, swivel_gradient

__all__ = [
    "SWIVEL_DOWN",
    "palm_normal",
    "roll_error",
    "swivel_angle",
    "swivel_gradient",
]
