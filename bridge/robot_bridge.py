"""The robot-facing core of the bridge: check, send, read back, report.

:class:`RobotBridge` plays one trajectory on a NAO (real or simulated):

1. the trajectory becomes command frames at the timeline's rate, and every
   frame is checked against the joints' position, speed, acceleration and jerk
   limits, and the lines between frames against the trajectory (within a
   degree); one bad frame refuses the whole trajectory, before the robot is
   even contacted;
2. the robot is connected (again, if it went away); it must be awake
   (``bridge.awake``, unless the bridge was told otherwise) and allow every
   joint at least the bridge's range and speed (``bridge.robot_limits``,
   asked once per connection); the arm's commanded angles are read once they
   hold still and no motion task holds its joints (``bridge.at_rest``: an
   arm still moving, or held by another task, is busy); a limp arm (a
   joint's stiffness below 0.5) whose sensors say, once they hold still,
   that it is elsewhere (it sagged or was moved) counts as where it is, and
   its command is moved there before it is stiffened, so that stiffening
   holds it there (``bridge.limp_arm``); where the arm is must be within
   the bridge's range, checked before the hold and the stiffening
   (``bridge.posture_range``), as the approach move is; a refusal after
   either went out says so; with the approach off, an arm away
   from the trajectory's start refuses it here; the arm's joints are
   stiffened, and if the arm is not at the start, or the first frame from
   where it is breaks a limit (``bridge.start_gap``), a slow approach move
   (checked the same way) brings it there, and it must then be there, and
   still stiff (``bridge.arm_state``); a movement that would end after its
   caller stops waiting is not started: checked before the robot is
   contacted, before the approach and again just before the frames go out
   (``bridge.in_time``); the client connects again by itself after a drop,
   perhaps to another robot, so each command that moves the arm goes out
   only on the connection the robot was checked on (``bridge.same_connection``);
3. the frames go out as one ``angleInterpolation`` call while the measured
   angles are sampled at 100 Hz on a connection of their own, so that they
   never wait behind a call still on its way (``bridge.playback``); a robot
   given up mid-movement is asked to stop the arm (``naoqi_client.STOP``)
   first, and is stopped every control cycle until the call has ended
   (``bridge.stopper``), taking no new movement meanwhile; a call the robot
   answered well before its duration was ended there, and an arm no longer
   stiff after it was let go during it: both are errors, not reports; a
   bridge that is stopping and can wait no longer for the movement's end
   stops the arm the same way (:meth:`RobotBridge.cut_short`, ``bridge.cut``);
4. the answer is the executed joint states and the tracking report (RMS and
   largest error per joint, degrees).

The Zenoh wrapper (the bridge process) only feeds requests to
:meth:`RobotBridge.handle` and publishes what it returns.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

import numpy as np

from bridge.almotion import angle_interpolation_call
from bridge.approach import approach_frames
from bridge.arm_state import check_at_start, check_still_stiff
from bridge.at_rest import angles_at_rest, read_angles
from bridge.awake import check_awake
from bridge.body_clearance import check_frames_clear
from bridge.checked_frames import checked_frames
from bridge.checks import check_frames
from bridge.cut import Cut
from bridge.frames import DEFAULT_RATE, check_rate
from bridge.hand import with_hand
from bridge.in_time import AFTER, CallDelay, CallerGone, check_in_time
from bridge.limits import FrameLimits
from bridge.limp_arm import hold_command, limp_posture
from bridge.naoqi_client import NaoqiClient
from bridge.playback import SAMPLE_PERIOD, play_and_sample
from bridge.posture_range import check_in_range
from bridge.robot_limits import RobotLimitsCheck
from bridge.same_connection import check_connection
from bridge.start_gap import needs_approach
from bridge.stop_order import StopOrder
from bridge.tracking import executed_states, tracking_report
from shared.bus.robot_routes import BRIDGE
from shared.errors import ServiceUnavailableError, TrajectoryRefusedError
from shared.messages import (
    CommandFrames,
    ExecuteReply,
    ExecuteRequest,
    JointState,
    Trajectory,
)
from shared.robot import Side
from shared.robot.body import BODY, BodyPart
from shared.robot.other_arm import with_other_arm

#: What became of a trajectory refused once the approach brought the arm there.
ARRIVED = "the arm is at the trajectory's start; nothing of the trajectory was sent"
#: What was sent before a refusal after a limp arm was held and stiffened.
HELD = (
    "the limp arm's command was moved to where it hung and the arm stiffened "
    "there; no movement was sent"
)
#: What was sent before a refusal after the arm was stiffened where it was.
STIFFENED = "the arm was stiffened where it was; no movement was sent"

StateCallback = Callable[[JointState], None]
FramesCallback = Callable[[CommandFrames], None]
#: Called with the approach's length [s] as it starts.
ApproachCallback = Callable[[float], None]
#: Called with when the trajectory's call reached the robot [s, monotonic].
ArrivalCallback = Callable[[float], None]


class RobotBridge:
    """Plays trajectories on the robot behind ``client``.

    Attributes:
        client: The robot's ALMotion over NAOqi.
        rate: Default frame rate of the command frames [Hz].
        sample_period: Time between readings of the measured angles [s].
        require_awake: Refuse a robot not awake (``robotIsWakeUp()``).
    """

    def __init__(
        self,
        client: NaoqiClient,
        *,
        rate: float = DEFAULT_RATE,
        limits: dict[Side, FrameLimits] | None = None,
        sample_period: float = SAMPLE_PERIOD,
        require_awake: bool = True,
    ) -> None:
        """Set up the bridge; nothing is sent yet.

        Args:
            client: The robot.
            rate: Default frame rate [Hz].
            limits: Per-arm limits; default: the robot description's, with
                :mod:`bridge.limits`' default accelerations.
            sample_period: Time between readings [s].
            require_awake: Refuse to play on a robot that is not awake
                (False: ``--allow-not-awake``, a robot held up otherwise).

        Raises:
            InvalidInputError: ``rate`` is no frame rate a request could name.
        """
        self.client = client
        self.rate = check_rate(rate, "the bridge's frame rate")
        self.sample_period = sample_period
        self.require_awake = require_awake
        self._limits = limits or {side: FrameLimits.for_arm(side) for side in Side}
        self._robot_limits = RobotLimitsCheck()
        self._stopping = threading.Event()
        self._cut = Cut()
        self._call_delay = CallDelay()

    def stop(self) -> None:
        """Send no new command from now on (the bridge process is stopping).

        A call already sent plays on (until :meth:`cut_short`); a request
        being served is refused at its next step (:meth:`refuse_if_stopping`).
        """
        self._stopping.set()

    def cut_short(self, why: str) -> None:
        """Stop the arm of the movement playing, if any, and from now on.

        The request playing it fails with "the bridge is stopping; it
        stopped the arm at about t = X s of Y s (``why``): ..." (``bridge.cut``).
        """
        self._cut.order(why)

    def refuse_if_stopping(self, outcome: str) -> None:
        """Raise if :meth:`stop` was called; ``outcome``: what was sent.

        Raises:
            ServiceUnavailableError: the bridge is stopping.
        """
        if self._stopping.is_set():
            raise ServiceUnavailableError(
                BRIDGE, reason=f"the bridge is stopping; {outcome}"
            )

    def limits(self, arm: Side) -> FrameLimits:
        """The limits used for ``arm``."""
        return self._limits[arm]

    def frames(
        self, trajectory: Trajectory, rate: float | None = None
    ) -> CommandFrames:
        """Checked command frames of ``trajectory`` (its hand too); nothing is sent.

        Raises:
            TrajectoryRefusedError: naming the first frame over a limit,
                the joint whose frames stray furthest from the trajectory, or
                the sample whose velocity disagrees with the positions.
        """
        limits = self.limits(trajectory.arm)
        return checked_frames(trajectory, rate or self.rate, limits)

    def handle(
        self,
        request: ExecuteRequest,
        on_state: StateCallback | None = None,
        on_play: FramesCallback | None = None,
        until: float | None = None,
        *,
        on_approach: ApproachCallback | None = None,
        on_arrival: ArrivalCallback | None = None,
        frames: CommandFrames | None = None,
        stop: StopOrder | None = None,
        gone: CallerGone | None = None,
    ) -> ExecuteReply:
        """Answer an execute request (see :meth:`execute`)."""
        return self.execute(
            request.trajectory,
            rate=request.rate,
            approach=request.approach,
            on_state=on_state,
            on_play=on_play,
            until=until,
            on_approach=on_approach,
            on_arrival=on_arrival,
            frames=frames,
            stop=stop,
            gone=gone,
        )

    def execute(
        self,
        trajectory: Trajectory,
        *,
        rate: float | None = None,
        approach: bool = True,
        on_state: StateCallback | None = None,
        on_play: FramesCallback | None = None,
        until: float | None = None,
        on_approach: ApproachCallback | None = None,
        on_arrival: ArrivalCallback | None = None,
        frames: CommandFrames | None = None,
        stop: StopOrder | None = None,
        gone: CallerGone | None = None,
    ) -> ExecuteReply:
        """Play ``trajectory`` on the robot and report how well it followed.

        Args:
            trajectory: The trajectory [s, rad].
            rate: Frame rate [Hz]; default :attr:`rate`.
            approach: Move to the start first if the arm is elsewhere; if
                False, an arm away from the start refuses the trajectory.
            on_state: Called with each measured state during the movement.
            on_play: Called with the frames once every check has passed and
                the arm is at their start, just before they are sent; the
                time, the bridge's stop and ``stop`` are checked again after
                it (publishing the frames may wait for the network).
            until: When the caller stops waiting for the answer [s,
                monotonic clock]; ``None``: no deadline. A movement that
                would end later is not started (``bridge.in_time``).
            on_approach: Called with the approach's length [s] just before
                it is sent (not called if there is none).
            on_arrival: Called with when the trajectory's call reached the
                robot [s, monotonic], as soon as that is known.
            frames: The frames of ``trajectory`` at ``rate``, checked
                already (:meth:`frames`); None: they are made and checked
                here.
            stop: The operator's order to stop this execution
                (``bridge/stop``): seen between two checks, and between two
                readings while a movement plays (the arm is stopped at once).
            gone: Whether the caller's session has ended (interrupted or
                killed); checked with ``until``: no movement is started for
                a caller who is gone. None: not known (the follower).

        Raises:
            TrajectoryRefusedError: a frame breaks a limit, or the velocities
                disagree with the positions (nothing sent).
            CallerDeadlineError: the movement would end after ``until``, or
                the caller's session ended (``CallerGoneError``): nothing
                sent, or (found after the approach) nothing of the trajectory.
            ServiceUnavailableError: the bridge is stopping (:meth:`stop`):
                nothing sent, or nothing after the approach; or it stopped
                the arm mid-movement (:meth:`cut_short`).
            RobotStateError: ``stop`` was ordered (``stopped``; the arm
                stopped where it was, or nothing was sent).
            RobotBusyError: the arm was still moving after a second.
            RobotUnavailableError: the robot cannot be reached, or went away
                during the movement (raised within 2 s of it going; asked to
                stop first), or overran it; or the bridge is still stopping
                the arm after giving up a call that has not ended (nothing
                sent).
            RobotCommandError: the robot refused a command.
            RobotStateError: the robot is not awake, or the arm rests
                outside the bridge's range (nothing sent); or the
                approach did not bring the arm to the start (nothing of the
                trajectory sent); or the client connected again since the
                robot was checked; or the robot ended a call early, or let
                the arm go limp during it.
            RobotLimitsError: the robot allows a joint less range or speed
                than the bridge's limits (nothing sent).
        """
        order = StopOrder() if stop is None else stop
        if frames is None:  # from the trajectory as given: its hand speeds if any
            frames = self.frames(trajectory, rate)
        trajectory, limits = with_hand(trajectory, self.limits(trajectory.arm))
        names = list(frames.joint_names)
        url, duration = self.client.url, frames.duration
        keys = len(frames.times) * len(frames.joint_names)
        overhead = self._call_delay.estimate(keys) + AFTER
        check_in_time(url, until, None, duration, "nothing was sent", overhead, gone)
        self.refuse_if_stopping("nothing was sent")
        order.check(url, "nothing was sent")
        self.client.refuse_while_stopping()
        self.client.motion()  # connected: the checks hold for this connection
        checked = self.client.connection
        if self.require_awake:
            check_awake(self.client)
        self._robot_limits.check(self.client, limits)
        current = angles_at_rest(self.client, names)
        limp = limp_posture(self.client, names)
        if limp is not None:  # stiffened, it would snap back to its command
            current = limp
        clear_of = self._keep_clear(frames, "nothing was sent")
        # all checked before the hold and the stiffening: a refusal sends nothing
        move = self._start_move(
            frames, current, limits, approach, limp is not None, clear_of=clear_of
        )
        self.refuse_if_stopping("nothing was sent")
        order.check(url, "nothing was sent")
        check_connection(self.client, checked, "nothing was sent")
        if limp is not None:
            hold_command(self.client, names, limp, limits)
        sent = "nothing was sent"
        if self.client.stiffen(names):  # another client may have moved it meanwhile
            sent = HELD if limp is not None else STIFFENED
            current = angles_at_rest(self.client, names)
            clear_of = self._keep_clear(frames, sent)
            move = self._start_move(
                frames, current, limits, approach, False, sent, clear_of
            )
        approach_time = 0.0 if move is None else move.duration
        check_in_time(url, until, approach_time, duration, sent, overhead, gone)
        self.refuse_if_stopping(sent)
        order.check(url, sent)
        if move is not None:
            check_connection(self.client, checked, sent)
            if on_approach is not None:
                on_approach(move.duration)
            self._approach(frames, move, on_state, order)
        check_in_time(url, until, 0.0, duration, ARRIVED, overhead, gone)
        self.refuse_if_stopping(ARRIVED if move is not None else sent)
        order.check(url, ARRIVED if move is not None else sent)
        if on_play is not None:  # may wait: a bus put blocks up to 5 s (Bus.publish)
            on_play(frames)
            check_in_time(url, until, 0.0, duration, ARRIVED, overhead, gone)
            self.refuse_if_stopping(ARRIVED if move is not None else sent)
            order.check(url, ARRIVED if move is not None else sent)
        call = angle_interpolation_call(frames)
        # last, so that nothing but the call's own sending comes after it
        check_connection(
            self.client,
            checked,
            ARRIVED if move is not None else sent,
        )
        samples = play_and_sample(
            self.client,
            call,
            period=self.sample_period,
            on_sample=on_state,
            on_arrival=on_arrival,
            cut=self._cut,
            stop=order,
        )
        self._call_delay.learn(keys, samples.start_delay)
        check_still_stiff(
            self.client,
            names,
            _chain(frames.arm),
            "the movement was not played as sent; the arm is limp where it stopped",
        )
        states = executed_states(trajectory, samples)
        return ExecuteReply(
            report=tracking_report(states, trajectory),
            states=states,
            frames=len(frames.times),
            approach_duration=approach_time,
        )

    def _start_move(
        self,
        frames: CommandFrames,
        current: np.ndarray,
        limits: FrameLimits,
        approach: bool,
        limp: bool,
        sent: str = "nothing was sent",
        clear_of: tuple[BodyPart, ...] = BODY,
    ) -> CommandFrames | None:
        """The checked approach from ``current`` [rad] (n,), or None if none is needed.

        ``limits`` are the frames' joints' (the hand's too, if they move
        it); ``limp``: ``current`` is where a limp arm hangs (measured);
        ``sent``: what was sent so far, for the errors; ``clear_of``: what
        the approach keeps clear of (NAO's body, and the other arm).

        Raises:
            RobotStateError: a joint at ``current`` is outside its range.
            TrajectoryRefusedError: the arm is away from the start and
                ``approach`` is off, or the approach breaks a limit.
        """
        url = self.client.url
        check_in_range(url, current, limits, limp=limp, outcome=sent)
        try:
            if not needs_approach(frames, current, limits, approach):
                return None
            return self._approach_move(frames, current, limits, clear_of)
        except TrajectoryRefusedError as error:
            raise error.instead(sent) from None

    def _keep_clear(self, frames: CommandFrames, sent: str) -> tuple[BodyPart, ...]:
        """NAO's body and the other arm where it is; ``frames`` checked against them.

        The other arm is read as measured (a limp arm is where it hangs, not
        where it was commanded) and taken to stay there while this one moves.

        Raises:
            TrajectoryRefusedError: a frame comes near the other arm
                (``sent``: what was sent so far).
            RobotCommandError: the robot gave angles that are not numbers.
        """
        other = Side.LEFT if Side.parse(frames.arm) is Side.RIGHT else Side.RIGHT
        still = read_angles(self.client, list(other.joint_names), True)
        clear_of = with_other_arm(frames.arm, still)
        try:
            check_frames_clear(frames, "frame", clear_of)
        except TrajectoryRefusedError as error:
            raise error.instead(sent) from None
        return clear_of

    def _approach_move(
        self,
        frames: CommandFrames,
        current: np.ndarray,
        limits: FrameLimits,
        clear_of: tuple[BodyPart, ...] = BODY,
    ) -> CommandFrames:
        """The checked move from ``current`` [rad] to the frames' start.

        ``limits`` are the frames' joints' (the hand's too, if they move it).

        Raises:
            TrajectoryRefusedError: the move breaks a limit (its frame 0 is
                where the arm is).
        """
        start = np.asarray(frames.start)
        move = approach_frames(frames.arm, current, start, limits, frames.rate)
        try:
            check_frames(move, limits)
            check_frames_clear(move, "approach frame", clear_of)
        except TrajectoryRefusedError as error:
            raise error.adding(
                " (in the approach move from where the arm is)"
            ) from None
        return move

    def _approach(
        self,
        frames: CommandFrames,
        move: CommandFrames,
        on_state: StateCallback | None = None,
        stop: StopOrder | None = None,
    ) -> None:
        """Play ``move``, which brings the arm to the start of ``frames``.

        ``on_state`` gets each state measured on the way (20 Hz), its time
        counted to the trajectory's start, so negative [s]: a recording then
        holds every measured state while the arm moves, the approach too.

        Raises:
            RobotStateError: the arm went limp, or did not arrive at the start.
        """
        start = np.asarray(frames.start)
        on_sample = None if on_state is None else _shifted(on_state, -move.duration)
        samples = play_and_sample(
            self.client,
            angle_interpolation_call(move),
            period=0.05,
            on_sample=on_sample,
            cut=self._cut,
            approach=True,
            stop=stop,
        )
        keys = len(move.times) * len(move.joint_names)
        self._call_delay.learn(keys, samples.start_delay)  # a small call: latency
        names = list(frames.joint_names)
        check_still_stiff(
            self.client, names, _chain(frames.arm), "nothing of the trajectory was sent"
        )
        check_at_start(self.client, names, start)


def _chain(arm: Side | str) -> str:
    """NAOqi's chain name of ``arm``: ``RArm`` or ``LArm``."""
    return Side.parse(arm).prefix + "Arm"


def _shifted(report: StateCallback, by: float) -> StateCallback:
    """``report`` for states whose times are moved by ``by`` [s]."""
    return lambda state: report(state.model_copy(update={"time": state.time + by}))
