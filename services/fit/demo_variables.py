"""The motion variables along a demonstrated trial.

Like the decision at a path point, each sample is seen with the trial's end
as the goal: the wrist's final position and, when the recording shows the
forearm's roll, the wrist frame's final orientation (W_R, ``roll``; without
it W_R is not observed).
"""

from __future__ import annotations

import numpy as np

from services.fit.roll import roll_to_go
from services.fit.variables import motion_variables
from shared.demos.trial import Trial


def trial_variables(trial: Trial, upper: float, forearm: float) -> np.ndarray:
    """The five variables at each sample of ``trial``, shape (n, 5).

    Args:
        trial: A retargeted trial.
        upper: Upper arm length the trial was retargeted to, L_u [m].
        forearm: Forearm length the trial was retargeted to, L_f [m].
    """
    roll = None
    if trial.wrist_frame is not None:
        axis = trial.wrist_frame[:, :, 1]
        roll = roll_to_go(
            trial.shoulder,
            trial.elbow,
            trial.wrist,
            axis,
            trial.target,
            axis[-1],
            upper,
            forearm,
        )
    return motion_variables(
        trial.shoulder, trial.elbow, trial.wrist, trial.target, upper, forearm, roll
    )
