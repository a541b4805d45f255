"""Play an ``angleInterpolation`` call and sample the measured angles meanwhile.

The call runs asynchronously on the client's command session; while it
runs, ``getAngles(names, True)`` is read every ``period`` seconds on the
watch session, a connection of its own (on the call's connection a reading
waits until the whole call has arrived: over a slow link, more than a
second for a large call, and a robot about to move looked silent). The
readings keep a fixed schedule from the call's start (``next_reading``),
so a reading's round trip does not stretch the period. A sample's time is
the middle of its request and its answer, counted from the moment the call
left (after libqi converted its arguments); it is uncertain by half the
round trip, which is kept with the sample.

The robot counts the keys from when it has received the call, which can be
well after the call left: a long call at a high frame rate is a large
message to carry and to parse (libqi sends 26 bytes a key, an angle and a
time each as a tagged double: 130 kB for 1000 frames of five joints; 44 000
frames began on the simulated NAO 0.5-0.7 s after they left, over
loopback). Two measures of that moment:

- a small call sent right behind it on the same connection (the *arrival
  mark*, a ``getAngles``) is answered once the whole call has arrived,
  since libqi sends and the robot reads one connection's messages in order;
  the movement must end within its duration + ``OVERRUN`` of that answer;
- ``angleInterpolation`` answers when the movement ends, the call's
  duration after the robot began it, so the answer's arrival less that
  duration is when the robot began, at the latest (early by the answer's
  own trip and up to a control cycle). How long after the call left that
  was is kept with the samples (``start_delay``).

The robot is declared lost with a
:class:`~shared.errors.RobotUnavailableError` if a connection drops, if no
reading is answered for ``LOST_AFTER`` seconds, or if the movement runs
``OVERRUN`` past its last key counted from the call's arrival. A call still
on its way is waited for as long as the robot answers the readings, up to
its duration + ``OVERRUN`` (``overdue``). Before giving up, the bridge asks
the robot to stop the arm's motion tasks
(``ALMotion.killTasksUsingResources``, on every session still up), so a
robot still there does not go on moving unwatched; a call not known to have
ended may still start (a stop served while the robot is still checking the
call ends nothing), so the client goes on stopping the arm every control
cycle from the call's arrival until the call has ended
(:mod:`bridge.stopper`).

A call the robot ends before its last key (its motion task killed: by
``killAll``, ``killTasksUsingResources``, the fall manager, another client)
may fail, or may return normally, as if it had played: an answer more than
``EARLY_END`` before the call's duration, counted from its arrival mark
(the robot counts the keys from when it received the call, not from when
the call left: counted from leaving, a kill within the call's travel time
of its end passed as a clean execution), is such an end, and raises a
:class:`~shared.errors.RobotStateError` ("the robot ended the movement at
t = X s of Y s"), unless it returned no earlier than its duration after
it left with its joints commanded at its last key (``_played_through``: its
mark was answered late, another client's blocking calls holding the
robot's worker threads). A call that fails is such an end too if the robot had
begun it: its joints' command moved since the arrival mark was answered
with it (a refused call moves nothing; it is a
:class:`~shared.errors.RobotCommandError`). Either error says whether the
arm is limp once its stiffness holds still (``arm_state.limp_joint``: a
rest or the fall manager releases it as it kills the call).

A bridge that is stopping and can wait no longer for the movement's end
orders it cut (``bridge.cut``): the arm is stopped the same way as when the
robot is given up, and the caller told where (``service_unavailable``, "the
bridge is stopping; it stopped the arm at about t = X s of Y s ...").
An operator's ``bridge/stop`` query orders the execution stopped
(``bridge.stop_order``): the arm is stopped the same way, at once, and the
caller told where (``robot_state``, stopped: "a bridge/stop query stopped
the movement at t = X s of Y s").
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from bridge.almotion import AngleInterpolationCall
from bridge.arm_state import limp_joint
from bridge.cut import Cut
from bridge.naoqi_client import NaoqiClient
from bridge.qi_future import POLL, robot_reason, wait_future
from bridge.stop_order import StopOrder
from shared.errors import (
    RobotStateError,
    RobotUnavailableError,
    ServiceUnavailableError,
)
from shared.messages import JointState

#: Time between two readings of the measured angles [s] (100 Hz).
SAMPLE_PERIOD = 0.01
#: A robot that answers no reading for this long is lost [s].
LOST_AFTER = 1.0
#: Time allowed past the call's last key, counted from its arrival, before
#: the robot is declared lost [s].
OVERRUN = 1.0
#: Longest wait for the answer to the stop (``naoqi_client.STOP``) when the
#: robot is given up [s].
HALT_WAIT = 0.25
#: A call answered more than this before its duration, counted from its
#: arrival mark (when the robot had it all), was ended by the robot [s].
EARLY_END = 0.1
#: A failed call whose joints' commanded angles moved more than this since
#: its arrival mark had begun: the robot ended it, it did not refuse it [rad].
MOVED = 1e-6
#: A call's joints commanded this close to its last key are at it: rounding
#: (NAOqi's angles are 32-bit floats: 2.4e-7 rad at 2 rad) [rad].
AT_LAST_KEY = 1e-5


class Samples(NamedTuple):
    """Measured angles during a call.

    Attributes:
        times: Sample times from the call's start [s], shape (k,).
        positions: Measured angles [rad], shape (k, n).
        round_trips: Time from each request to its answer [s], shape (k,);
            a sample's time is uncertain by half of it. ``None``: exact times.
        start_delay: How long after the call left the robot began it, at
            most [s]: its answer came this much later than the call's
            duration after it left (0 if not later).
    """

    times: np.ndarray
    positions: np.ndarray
    round_trips: np.ndarray | None = None
    start_delay: float = 0.0


class _Reader:
    """Reads the measured angles of ``names`` with a timeout."""

    def __init__(self, motion: Any, names: list[str], timeout: float) -> None:
        self.motion, self.names, self.timeout = motion, names, timeout

    def read(self, within: float) -> tuple[float, float, list[float] | None, str]:
        """(time [s, monotonic], round trip [s], angles or None, error text).

        Waits at most ``within`` [s] (and :attr:`timeout`) for the answer.
        """
        sent = time.monotonic()
        future = self.motion.getAngles(self.names, True, _async=True)
        finished = wait_future(future, min(self.timeout, within))
        answered = time.monotonic()
        if not finished:
            future.cancel()
            return answered, answered - sent, None, "no answer to getAngles"
        if future.hasError():
            return answered, answered - sent, None, future.error()
        return 0.5 * (sent + answered), answered - sent, list(future.value()), ""


class _Arrival:
    """When the call reached the robot: the answer to a mark sent behind it.

    The mark is a ``getAngles`` on the call's own session: libqi sends one
    connection's messages in order and the robot reads them in order, so
    it is answered only once the whole call has arrived. Its answer, the
    commanded angles then, tells a call the robot refused (the command
    never moved from it) from one it began.
    """

    def __init__(self, motion: Any, names: list[str]) -> None:
        self._stamps: list[float] = []  # stamped on libqi's thread
        self._future = motion.getAngles(names, False, _async=True)
        self._future.addCallback(lambda _: self._stamps.append(time.monotonic()))

    @property
    def time(self) -> float | None:
        """When the mark was answered [s, monotonic]; None while on its way."""
        return self._stamps[0] if self._stamps else None

    def command(self, wait: float) -> np.ndarray | None:
        """The commanded angles [rad], (n,), the mark was answered with.

        Waits at most ``wait`` [s] for the answer; None without one.
        """
        if not wait_future(self._future, wait) or self._future.hasError():
            return None
        return np.array(self._future.value(), dtype=float)


def overdue(
    start: float, arrival: float | None, duration: float, now: float
) -> str | None:
    """Why a call is overdue at ``now``, or None if it is not.

    Args:
        start: When the call left [s, monotonic].
        arrival: When it reached the robot [s, monotonic]; None: not yet.
        duration: The call's last key [s].
        now: The time [s, monotonic].

    A call must reach the robot within ``duration + OVERRUN`` of leaving (a
    link that carries it slower than it plays cannot be watched), and end
    within ``duration + OVERRUN`` of reaching it.
    """
    allowed = duration + OVERRUN
    if arrival is None and now - start > allowed:
        return (
            f"the call did not reach the robot within {allowed:.2f} s of leaving "
            f"(its duration + {OVERRUN:g} s): the link is too slow for it"
        )
    if arrival is not None and now - arrival > allowed:
        return (
            f"the movement did not end {OVERRUN:g} s after its last key "
            "(counted from when the call reached the robot)"
        )
    return None


def next_reading(due: float, period: float, now: float) -> float:
    """When to read next [s, monotonic]: one ``period`` [s] after ``due``.

    Readings keep to a fixed schedule, so the rate is ``1 / period`` however
    long each round trip takes (waiting ``period`` after each answer made
    93.7 Hz of 100). A reading that falls a whole period or more behind
    (a slow answer) does not bring a burst of catch-up readings: the
    schedule starts again from ``now``.
    """
    due += period
    return due if due > now - period else now


def play_and_sample(
    client: NaoqiClient,
    call: AngleInterpolationCall,
    *,
    period: float = SAMPLE_PERIOD,
    on_sample: Callable[[JointState], None] | None = None,
    on_arrival: Callable[[float], None] | None = None,
    cut: Cut | None = None,
    approach: bool = False,
    stop: StopOrder | None = None,
) -> Samples:
    """Send ``call`` and sample the measured angles until it ends.

    Args:
        client: The robot.
        call: The ``angleInterpolation`` arguments.
        period: Time between readings [s].
        on_sample: Called with each measured state (e.g. to publish it).
        on_arrival: Called once with when the call reached the robot [s,
            monotonic] (its arrival mark's answer), as soon as that is seen.
        cut: Once ordered, the arm is stopped as when the robot is given up
            (within a reading's wait), and the cut's error raised.
        approach: ``call`` is the approach to a trajectory's start: an end
            before its last key is said as "the robot ended the approach".
        stop: Once ordered (``bridge/stop``), the arm is stopped as when
            the robot is given up (within a reading's wait), and the
            order's error raised.

    Raises:
        RobotUnavailableError: the robot went away during the call (within
            :data:`LOST_AFTER` + :data:`HALT_WAIT` seconds of it going), or
            its movement ran :data:`OVERRUN` past its end; the robot was
            asked to stop first, and the client goes on stopping the arm
            until the call has ended.
        RobotCommandError: the robot refused the call (it moved nothing).
        RobotStateError: the robot answered the call more than
            :data:`EARLY_END` before its duration, or failed it after
            moving its command: it ended it early.
        ServiceUnavailableError: ``cut`` was ordered (the bridge is
            stopping): the arm was stopped, the client goes on stopping it
            until the call has ended.
        RobotStateError: ``stop`` was ordered: the arm was stopped the same
            way (``stopped``, saying the ``bridge/stop`` query stopped it).
    """
    motion = client.motion()
    reader = _Reader(client.watch(), call.names, min(period * 20, LOST_AFTER / 2))
    future = motion.angleInterpolation(*call, _async=True)
    # The samples' clock starts when the call leaves, after libqi has
    # converted its arguments (milliseconds for a long trajectory), not before.
    start = time.monotonic()
    arrival = _Arrival(motion, call.names)
    answered: list[float] = []  # stamped on libqi's thread, not at the next poll
    future.addCallback(lambda _: answered.append(time.monotonic()))
    times: list[float] = []
    rows: list[list[float]] = []
    round_trips: list[float] = []
    last_answer = due = start
    told = False  # on_arrival was called
    while not future.isFinished():
        # a reading that cannot come in time no longer delays the verdict
        stamp, round_trip, angles, problem = reader.read(
            max(POLL, last_answer + LOST_AFTER - time.monotonic())
        )
        elapsed = stamp - start
        if angles is not None:
            last_answer = stamp
            times.append(elapsed)
            rows.append(angles)
            round_trips.append(round_trip)
            if on_sample is not None:
                on_sample(
                    JointState(time=elapsed, joint_names=call.names, positions=angles)
                )
        elif not (client.connected and client.watching) or (
            stamp - last_answer > LOST_AFTER
        ):
            raise _give_up(
                client, future, call.names, problem, elapsed, arrival.time is None
            )
        if on_arrival is not None and not told and arrival.time is not None:
            told = True
            on_arrival(arrival.time)
        if cut is not None and cut.ordered:
            raise _cut_short(client, future, call, arrival.time, cut)
        if stop is not None and stop.ordered:
            raise _stopped(client, future, call, arrival.time, stop, approach)
        late = overdue(start, arrival.time, call.duration, time.monotonic())
        if late is not None:
            raise _give_up(
                client, future, call.names, late, elapsed, arrival.time is None
            )
        due = next_reading(due, period, time.monotonic())
        time.sleep(max(0.0, due - time.monotonic()))
    seen = time.monotonic()
    if future.hasError():
        elapsed = seen - start
        if not client.connected:  # the robot may play the call on, unwatched
            reason = robot_reason(future.error())
            raise _give_up(
                client, future, call.names, reason, elapsed, arrival.time is None
            )
        if not _began_moving(client, call.names, arrival):
            raise client.failure("angleInterpolation", future.error(), elapsed)
    end = min([seen, *answered])  # the callback may not have run yet
    played = end - _began(start, arrival.time, end)
    early = played < call.duration - EARLY_END
    if early and not future.hasError() and _played_through(client, call, end - start):
        played = call.duration  # its arrival mark was answered late, not a kill
    if future.hasError() or played < call.duration - EARLY_END:
        failed = robot_reason(future.error()) if future.hasError() else None
        raise _ended_early(
            client, call.names, played, call.duration, failed, end, approach
        )
    width = len(call.names)
    return Samples(
        np.array(times),
        np.array(rows, dtype=float).reshape(-1, width),
        np.array(round_trips),
        max(0.0, end - start - call.duration),
    )


def _began(start: float, arrival: float | None, end: float) -> float:
    """When the robot began the call, as far as the bridge can tell [s, monotonic].

    The answer to its arrival mark (``arrival``), if that came before the
    call's answer at ``end``; else when it left (``start``): a call whose
    answer overtook its mark is judged as before, from leaving.
    """
    return arrival if arrival is not None and start <= arrival <= end else start


def _played_through(
    client: NaoqiClient, call: AngleInterpolationCall, answered: float
) -> bool:
    """Whether a call that returned normally was played to its last key.

    ``answered``: how long after it left its answer came [s]; its arrival
    mark says it ended early.

    The mark is answered on one of the robot's worker threads: while
    another client's blocking calls hold them all, its answer comes late
    (1.3 s of 2.16 s on the simulated NAO, which played the whole call), and
    counted from it the call seems to end early. Played through: its
    answer came no earlier than its duration (less ``EARLY_END``) after it
    left, and the joints' commanded angles are its last key, within
    rounding (:data:`AT_LAST_KEY`). A call killed before its last key fails
    the second test: its command stopped where it was killed.

    Raises:
        RobotUnavailableError: the robot cannot be reached.
    """
    if answered < call.duration - EARLY_END:
        return False
    last = np.array([angles[-1] for angles in call.angle_lists], dtype=float)
    now = client.get_angles(call.names, use_sensors=False)
    return bool(np.abs(now - last).max() <= AT_LAST_KEY)


def _began_moving(client: NaoqiClient, names: list[str], arrival: _Arrival) -> bool:
    """Whether the robot had begun the call that failed: it moved the command.

    A call the robot refuses moves nothing: the commanded angles of
    ``names`` are still those its arrival mark was answered with. A call
    killed once begun (``killAll``, ``rest``, the fall manager; a robot may
    answer it with an error) left them where it was killed. A refusal can
    come well after the mark (a large call is checked for tenths of a
    second after it arrived), so the time alone does not tell them apart.

    Raises:
        RobotUnavailableError: the robot cannot be reached.
    """
    mark = arrival.command(client.call_timeout)
    if mark is None:
        return False
    now = client.get_angles(names, use_sensors=False)
    return bool(np.abs(now - mark).max() > MOVED)


#: Words of a failed call's reason that say its motion task was killed
#: (the sim's "angleInterpolation was interrupted: killAll"), lower case.
KILL_WORDS = ("kill", "interrupt")


def _ended_early(
    client: NaoqiClient,
    names: list[str],
    played: float,
    duration: float,
    failed: str | None,
    ended: float,
    approach: bool = False,
) -> RobotStateError:
    """The error for a call on ``names`` ended at ``played`` of ``duration`` [s].

    ``ended``: when the call's answer came [s, monotonic], the error's
    ``stopped_at`` (the follower drops what was queued before it);
    ``approach``: the call was the approach to the trajectory's start.

    ``failed``: the robot's reason if the call failed, None if it returned.
    A kill is said only where it is one: a call that returned early, or a
    reason naming a kill or an interruption (:data:`KILL_WORDS`); another
    failure (the sim's log on a full disk failed the call) is said as it
    is. The words say whether the arm is limp now
    (``arm_state.limp_joint``): a rest or the fall manager releases it as
    it kills the call.
    """
    how = "returned" if failed is None else f'failed ("{failed}")'
    killed = failed is None or any(w in failed.lower() for w in KILL_WORDS)
    cause = (
        ": its motion task was killed, by killAll, killTasksUsingResources, "
        "the fall manager or another client"
        if killed
        else ""
    )
    limp = limp_joint(client, names)
    phase = "approach"
    stopped = "the arm stopped where it was then"
    if approach:
        stopped += "; nothing of the trajectory was sent"
    return RobotStateError(
        client.url,
        f"the robot ended the {phase if approach else 'movement'} at "
        f"t = {played:.2f} s of {duration:.2f} s "
        f"(its call {how} before its last key{cause})",
        stopped_at=ended,
        phase=phase if approach else "trajectory",
        played=round(max(played, 0.0), 3),
        duration=round(duration, 3),
        outcome=stopped
        if limp is None
        else f"{stopped} and is limp ({limp}): a rest, the fall manager or "
        "another client released it",
    )


def _cut_short(
    client: NaoqiClient,
    future: Any,
    call: AngleInterpolationCall,
    arrival: float | None,
    cut: Cut,
) -> ServiceUnavailableError:
    """The error to raise when ``cut`` stops ``call`` (its libqi ``future``).

    The arm is stopped as when the robot is given up (:func:`_give_up`),
    but the robot is not declared lost: it answers.
    """
    now = time.monotonic()
    outcome = client.halt(HALT_WAIT, call.names, future, arrival is not None)
    if arrival is None:
        return cut.error_on_its_way(call.duration, outcome)
    played = min(max(now - arrival, 0.0), call.duration)
    return cut.error(played, call.duration, outcome)


def _stopped(
    client: NaoqiClient,
    future: Any,
    call: AngleInterpolationCall,
    arrival: float | None,
    stop: StopOrder,
    approach: bool,
) -> RobotStateError:
    """The error to raise when ``stop`` stops ``call`` (its libqi ``future``).

    The arm is stopped as when the robot is given up (:func:`_give_up`):
    ``killTasksUsingResources`` on its joints, again until the call has
    ended; the robot is not declared lost. The error says the arm stopped
    only if the robot confirmed it (it answered the call, which has then
    ended); else that the stop was sent and the robot has not confirmed it.
    """
    now = time.monotonic()
    outcome = client.halt(HALT_WAIT, call.names, future, arrival is not None)
    played = None if arrival is None else min(max(now - arrival, 0.0), call.duration)
    stopped = (
        "the arm stopped where it was then"
        if outcome.confirmed
        else "the stop was sent; the robot has not confirmed it"
    )
    if approach:
        stopped += "; nothing of the trajectory was sent"
    return stop.error(
        client.url,
        f"{stopped} ({outcome})",
        phase="approach" if approach else "trajectory",
        played=played,
        duration=call.duration,
    )


def _give_up(
    client: NaoqiClient,
    call: Any,
    names: list[str],
    problem: str,
    elapsed: float,
    on_its_way: bool,
) -> RobotUnavailableError:
    """The error to raise when giving up ``call`` (a libqi future) on ``names``.

    The robot is asked to stop those joints' motion first, and the client
    goes on stopping them until the call has ended
    (:meth:`~bridge.naoqi_client.NaoqiClient.halt`). The call is not
    cancelled: its future must finish with the robot's own answer.
    """
    outcome = client.halt(HALT_WAIT, names, call, not on_its_way)
    return client.lost(f"{problem}; {outcome}", elapsed)
