"""The motion decision (paper Section III.B-C): which primitive drives each point.

- ``information``: transient (conditional) mutual information, eq. 5-6, and
  their accumulation, eq. 7-8; ``accumulate``: g of every primitive term by
  term along the network.
- ``decider``: the model compiled for fast decisions (eq. 10);
  ``point.decide_point``: one path point from the arm's kinematics.
- ``path.decide_path``: the decision inside the IK tracker's loop, giving the
  ``Decision`` message and the joint path.
- ``agreement``: the decision against demonstration labels (held-out check);
  ``grid_table``: the paper's Table 4 on NAO; ``plot``: Fig. 7 as PNG.

The algorithm lives here; ``service.py`` is the thin Zenoh wrapper.
"""

from services.decide.decider import CANDIDATES, Choice, Decider
from services.decide.path import decide_path, decide_wrist_path
from services.decide.point import DecidingArm, decide_point

__all__ = [
    "CANDIDATES",
    "Choice",
    "Decider",
    "DecidingArm",
    "decide_path",
    "decide_point",
    "decide_wrist_path",
]
