"""Coefficients of the human performance measures, with their defaults."""

from __future__ import annotations

from pydantic import Field

from shared.messages.base import Message


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
    """

    mu: float = Field(default=0.03, ge=0.0)
    omega: float = Field(default=0.01, ge=0.0)
    wrist_centre: float = 0.0
    k1: float = Field(default=1.0, ge=0.0)
    k2: float = Field(default=1.0, ge=0.0)
    swivel_weight: float = Field(default=0.05, gt=0.0)
