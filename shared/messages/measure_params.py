"""Coefficients of the human performance measures, with their defaults.

A message, so that a plan request (and the decide and ik stage requests
made from it) can carry its own; the IK's measures read them as floats.

The defaults of mu and omega are the weights ``armplan fit`` fitted on the
shipped demonstrations (``services.fit.weights``), the ones the shipped
motion model carries; ``tests/test_fit_weights.py`` checks they agree.
Before the fit they were set by hand (mu 0.03, omega 0.01).
"""

from __future__ import annotations

import math

from pydantic import Field

from shared.messages.base import Message

#: Largest weight a request may give a measure.
MOST = 1000.0


class MeasureParams(Message):
    """Weights of TPE, NTPE and H_G (equations 17-21).

    Attributes:
        mu: Torsion-spring stiffness on the elbow swivel angle [J/rad^2] (eq. 17).
        omega: Weight of wrist discomfort [J/rad^2] (eq. 19).
        wrist_centre: Centre angle of WristYaw theta_N,wa [rad] (eq. 19): the
            middle of its range, after the paper's reference [31].
        k1: Weight of elbow travel in H_G [J/m] (eq. 21).
        k2: Weight of NTPE in H_G [-] (eq. 21).
        swivel_weight: Stiffness pulling the swivel to a goal, for the
            function primitive S_R E_P W_R [J/rad^2].

    Each weight is at most ``MOST`` (the defaults are 0 to 1): the
    null-space step is capped, but a gradient that overflows would make it
    NaN. The centre angle lies within one turn either way.
    """

    mu: float = Field(default=0.0, ge=0.0, le=MOST)
    omega: float = Field(default=0.001051, ge=0.0, le=MOST)
    wrist_centre: float = Field(default=0.0, ge=-math.pi, le=math.pi)
    k1: float = Field(default=1.0, ge=0.0, le=MOST)
    k2: float = Field(default=1.0, ge=0.0, le=MOST)
    swivel_weight: float = Field(default=0.05, gt=0.0, le=MOST)
