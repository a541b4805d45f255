"""The primitive decision per moment, as a channel Foxglove's Plot panel draws.

One :class:`PrimitiveSample` per path point: the arm it moves (a session
planning both arms records both on one channel; filter on ``arm``), the
winning primitive's name, its number in Table 1's order (``index``, 0..9, a
plottable step curve) and every candidate's accumulated mutual information
g. Foxglove message paths cannot name a key with spaces, so ``g`` is keyed
by the primitive's name with spaces replaced by ``_`` (``"S_R E_P W_P"``
-> ``S_R_E_P_W_P``): plot ``/decision.index`` and ``/decision.g.S_R_E_P_W_P``, and
``/decision{arm=="left"}.index`` for the left arm alone.
"""

from __future__ import annotations

from collections.abc import Iterator

from pydantic import Field

from shared.messages import Decision, Message, Trajectory
from shared.primitives import PRIMITIVES
from shared.robot.side import SideAnyCase

#: Primitive names in Table 1's order; a sample's ``index`` points into it.
PRIMITIVE_NAMES: tuple[str, ...] = tuple(p.name for p in PRIMITIVES)


class PrimitiveSample(Message):
    """The primitive that drives the arm at one moment.

    Attributes:
        arm: The arm the primitive drives, ``"right"`` or ``"left"``.
        time: Time of the path point from the path's start [s] (a decision's
            on its wrist path's own clock, each reach's from 0; its log
            time is the trajectory's moment there).
        primitive: The winner's name, e.g. ``"S_R E_P W_P"``.
        index: Its position in Table 1's order (0..9); -1 if unknown.
        g: Accumulated mutual information of each candidate [nat], keyed by
            the name with ``_`` for spaces (empty when only labels are known).
    """

    arm: SideAnyCase
    time: float
    primitive: str
    index: int = Field(ge=-1)
    g: dict[str, float] = Field(default_factory=dict)


def plot_key(name: str) -> str:
    """``name`` as a key Foxglove's message paths accept (spaces to ``_``)."""
    return name.replace(" ", "_")


def primitive_index(name: str) -> int:
    """Position of primitive ``name`` in Table 1's order; -1 if unknown."""
    return PRIMITIVE_NAMES.index(name) if name in PRIMITIVE_NAMES else -1


def decision_samples(decision: Decision) -> Iterator[PrimitiveSample]:
    """One sample per path point of ``decision``, made as it is taken."""
    keys = [plot_key(name) for name in decision.candidates]
    for t, name, row in zip(
        decision.times, decision.primitives, decision.g, strict=True
    ):
        yield PrimitiveSample(
            arm=decision.arm,
            time=t,
            primitive=name,
            index=primitive_index(name),
            g=dict(zip(keys, row, strict=True)),
        )


def trajectory_samples(trajectory: Trajectory) -> Iterator[PrimitiveSample]:
    """One sample per trajectory sample, from its primitive labels, as taken."""
    for t, label in zip(trajectory.times, trajectory.primitives, strict=True):
        yield PrimitiveSample(
            arm=trajectory.arm, time=t, primitive=label, index=primitive_index(label)
        )
