"""One simulated joint: an ideal servo following its setpoint within its speed limit."""

from __future__ import annotations

from bridge.sim.joints import JointSpec
from bridge.sim.timeline import KeyTimeline

#: How fast a limp joint with a sag falls toward where it hangs [rad/s].
SAG_SPEED = 1.0


class SimJoint:
    """A joint's state: its position, stiffness and current command.

    The motor moves toward the setpoint at most ``velocity`` [rad/s]; the
    control cycle commits its position every 20 ms, and a reading between two
    cycles gives where the motor is at that moment (its encoder). A joint with
    stiffness 0 does not move, whatever it is commanded (or, with a ``sag``
    [s], falls toward where it hangs, its starting angle, at
    :data:`SAG_SPEED` for that long after it is let go, as a NAO's arm falls
    for about 0.3 s); stiffened again, it goes to its setpoint at its speed
    limit. A ``stop`` [rad] is as far as it goes down: a hand closing on an
    object stops at the object's width (its open fraction), whatever it is
    commanded.

    Attributes:
        spec: Name and limits.
        position: Position at the last commit [rad].
        time: Time of the last commit [s, sim clock].
    """

    def __init__(
        self,
        spec: JointSpec,
        position: float,
        time: float,
        stiffness: float = 0.0,
        sag: float = 0.0,
        stop: float | None = None,
    ) -> None:
        self.spec = spec
        self.stop = stop
        self.position = position if stop is None else max(position, stop)
        self.time = time
        self._hang, self._sag, self._sag_left = position, sag, sag
        self._hold = position
        self._timeline: KeyTimeline | None = None
        self._stiffness: KeyTimeline | None = None
        self._stiffness_hold = stiffness

    def setpoint(self, t: float) -> float:
        """The commanded angle at sim time ``t`` [rad]."""
        return self._timeline.at(t) if self._timeline else self._hold

    def stiffness(self, t: float) -> float:
        """Stiffness at sim time ``t`` (0..1)."""
        return self._stiffness.at(t) if self._stiffness else self._stiffness_hold

    def measured(self, t: float) -> float:
        """The motor's angle at sim time ``t`` (>= the last commit) [rad]."""
        angle = self._motor(t)
        return angle if self.stop is None else max(angle, self.stop)

    def _motor(self, t: float) -> float:
        """Where the motor would be at ``t`` with nothing in its way [rad]."""
        if self.stiffness(t) <= 0.0:
            fall = SAG_SPEED * min(max(0.0, t - self.time), self._sag_left)
            gap = self._hang - self.position
            return self.position + min(max(gap, -fall), fall)
        step = self.spec.velocity * max(0.0, t - self.time)
        error = self.setpoint(t) - self.position
        return self.position + min(max(error, -step), step)

    @property
    def moving(self) -> bool:
        """True while a command is running."""
        return self._timeline is not None

    def commit(self, t: float) -> None:
        """Advance the motor to sim time ``t`` [s]; end finished commands."""
        if t <= self.time:
            return
        self.position = self.measured(t)
        if self.stiffness(t) <= 0.0:
            self._sag_left = max(0.0, self._sag_left - (t - self.time))
        else:
            self._sag_left = self._sag
        self.time = t
        if self._timeline and t >= self._timeline.end_time:
            self._hold, self._timeline = self._timeline.final, None
        if self._stiffness and t >= self._stiffness.end_time:
            self._stiffness_hold, self._stiffness = self._stiffness.final, None

    def command(self, timeline: KeyTimeline | None) -> None:
        """Follow ``timeline`` from now on (``None``: hold the current setpoint)."""
        if timeline is None:
            self._hold = self.setpoint(self.time)
        self._timeline = timeline

    def command_stiffness(self, timeline: KeyTimeline) -> None:
        """Ramp the stiffness along ``timeline``."""
        self._stiffness = timeline
