"""Human performance measures H for the gradient projection method (eq. 14-21)."""

from services.ik.measures.base import Measure, NoMeasure
from services.ik.measures.elbow_travel import ElbowTravel
from services.ik.measures.grasp import GraspBlend
from services.ik.measures.ntpe import WristDiscomfortEnergy
from services.ik.measures.params import MeasureParams
from services.ik.measures.swivel_goal import SwivelGoal
from services.ik.measures.tpe import TotalPotentialEnergy

__all__ = [
    "ElbowTravel",
    "GraspBlend",
    "Measure",
    "MeasureParams",
    "NoMeasure",
    "SwivelGoal",
    "TotalPotentialEnergy",
    "WristDiscomfortEnergy",
]
