"""The runner of ``play.py`` (``bridge.python_export``): options, deadlines, stops.

The script runs on a robot's own Python 2.7 or any Python 3 with ``qi``,
without armplan, so this is its source text (:func:`runner_source`). It used
to make each ALMotion call blocking: Ctrl-C waited until the call ended
(the trajectory played to its end, then a raw ``KeyboardInterrupt``
traceback), a port that accepted TCP but never answered hung it forever in
``session.connect``, and everything after the address was dropped
(``play.py URL --help`` moved the arm). Now:

- ``argparse`` (Python 2.7 and 3): one optional ``URL``
  (``tcp://127.0.0.1:9559`` by default; one not ``tcp://HOST:PORT`` is
  refused as ``bridge.address`` refuses it), ``--timeout SECONDS`` (the
  connection's deadline, ``CONNECT_TIMEOUT`` by default), ``--help``
  (what it will play, nothing connected); anything else refused before
  connecting (exit 2); ``prog`` is the script's own file name.
- With ``qi``: the connection, the ALMotion service and every call are
  made with ``_async=True`` and their futures polled every ``POLL`` (so a
  signal is handled at once). A call may last its known duration (its
  keys' last time, the move to the start's too) and ``MARGIN`` more;
  then the arm is stopped and the script exits 1 naming the call.
- Before anything is sent, the script reads where the robot holds the
  other arm (``getAngles`` of its joints, from the sensors) and refuses,
  exit 1, a trajectory or a move to the start whose keys bring this arm
  within the body's margin of it (``bridge.script_body``): a plan made
  without ``other_arm`` knows nothing of that arm.
- The trajectory goes out only once the move to the start has brought the
  arm's command there (``check_arrived``, ``bridge.script_approach``): a
  move another client ended, its call returning without an error, exits 1;
  so does a trajectory that ended short of its last key (it printed
  ``played``).
- Played: one line on stdout, ``played N frames (D s) on URL``, exit 0.
- Ctrl-C, SIGTERM, SIGHUP: ``killTasksUsingResources`` on the script's
  joints every ``STOP_PERIOD`` until the running motion call has ended (a
  stop the robot serves before the call has taken effect ends nothing:
  ``bridge.stopper``), at most ``STOP_WAIT``; further signals are ignored
  meanwhile; then one line and exit 130, 143 or 129 (128 + the signal), as
  ``armplan`` does.
- With NAOqi's old ``naoqi`` module (``ALProxy``, when ``qi`` is missing):
  motion calls are posted (``motion.post``) and watched with ``isRunning``,
  so they can be stopped and bounded alike; its connection and reads have
  no deadline (``ALProxy`` offers none), and a posted call's refusal is in
  the robot's log, not raised.
"""

from __future__ import annotations

from bridge.script_approach import approach_source

#: Longest wait for the robot to answer the connection, by default [s].
CONNECT_TIMEOUT = 10.0
#: How long a call may overrun its known duration before it counts as stalled [s].
MARGIN = 5.0
#: Longest time the stops go on after a signal or a stalled call [s].
STOP_WAIT = 2.0
#: Time between two stops: ALMotion's control cycle [s].
STOP_PERIOD = 0.02
#: How long the stops go on when a motion call was being sent as the signal
#: came and its handle is unknown [s] (``bridge.stopper.SETTLE``).
STOP_SETTLE = 1.0
#: Time between two looks at a pending call [s].
POLL = 0.005

_SOURCE = '''

URL = "tcp://127.0.0.1:9559"
ARM, FRAMES, RATE, DURATION = {arm!r}, {frames!r}, {rate!r}, {duration!r}
SPEED = {speed!r}
CONNECT_TIMEOUT, MARGIN, POLL = {connect_timeout!r}, {margin!r}, {poll!r}
STOP_WAIT, STOP_PERIOD, STOP_SETTLE = {stop_wait!r}, {stop_period!r}, {stop_settle!r}
MOVES = ("angleInterpolation", "stiffnessInterpolation")
HOST_CHARACTERS = (
    "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-"
)


class Stopped(Exception):
    """A signal asked the script to stop; ``code`` is 128 + the signal.

    Once one is raised (or a call stalled), further signals are ignored:
    the stops that follow are bounded by STOP_WAIT.
    """

    raised = False

    def __init__(self, code, what):
        Exception.__init__(self, what)
        self.code = code


class Stalled(RuntimeError):
    """A call did not end within its known duration and MARGIN."""


def _wait(done, limit):
    """Call ``done()`` every POLL until true (True) or ``limit`` [s] passed (False)."""
    import time

    deadline = time.time() + limit
    while not done():
        if time.time() >= deadline:
            return False
        time.sleep(POLL)
    return True


def _flat(times):
    """Every number in a time argument (a number, a list, a list of lists)."""
    if isinstance(times, (list, tuple)):
        return [t for item in times for t in _flat(item)]
    return [float(times)]


class Motion(object):
    """ALMotion, each call bounded and stoppable (``session`` None: ``naoqi``)."""

    def __init__(self, proxy, session=None):
        self.proxy, self.session = proxy, session
        self.pending = None  # the motion call running: a qi future or a task id
        self.sending = False  # a motion call on its way, its handle not yet known
        self.sent = False  # a motion call was sent

    def __getattr__(self, method):
        if method.startswith("__"):
            raise AttributeError(method)

        def call(*args):
            known = max(_flat(args[2])) if method in MOVES else 0.0
            return self.call(method, args, known)

        return call

    def move_to(self, targets, share, others=()):
        """Move from the command to ``targets`` [rad]: minimum-jerk keys
        within ``share`` of the limits, clear of the body and ``others``
        (approach_keys), angleInterpolation; then RuntimeError unless the
        command is there (check_arrived)."""
        now = self.getAngles(names, False)
        keys, times = approach_keys(names, now, targets, share, others)
        self.angleInterpolation(names, keys, times, True)
        check_arrived(names, self.getAngles(names, False), targets)

    def call(self, method, args, known):
        """``method(*args)``'s result; Stalled after ``known`` + MARGIN [s]."""
        moves = method in MOVES
        self.sending, self.sent = moves, self.sent or moves
        if self.session is None and moves:
            task = getattr(self.proxy.post, method)(*args)
            self.pending, self.sending = task, False
            done = lambda: not self.proxy.isRunning(task)
        elif self.session is None:
            return getattr(self.proxy, method)(*args)
        else:
            future = getattr(self.proxy, method)(*args, _async=True)
            if moves:
                self.pending = future
            self.sending = False
            done = future.isFinished
        if not _wait(done, known + MARGIN):
            raise Stalled(
                "ALMotion.%s did not end within %.3g s (its %.3g s and a %g s "
                "margin): the robot stalled?" % (method, known + MARGIN, known, MARGIN)
            )
        self.pending = None
        return None if self.session is None else future.value()

    def _finished(self, call):
        if self.session is None:
            return not self.proxy.isRunning(call)
        return call.isFinished()

    def _send_stop(self):
        if self.session is None:
            return self.proxy.post.killTasksUsingResources(names)
        return self.proxy.killTasksUsingResources(names, _async=True)

    def stop(self):
        """killTasksUsingResources(names) every STOP_PERIOD until the motion
        call has ended and a stop was answered (True), at most STOP_WAIT (False)."""
        import time

        now = time.time()
        deadline, settle = now + STOP_WAIT, now + (STOP_SETTLE if self.sending else 0)
        stop, answered = None, False
        while True:
            try:
                if stop is None or self._finished(stop):
                    answered = answered or stop is not None
                    stop = self._send_stop()
                ended = self.pending is None or self._finished(self.pending)
            except RuntimeError:  # the connection dropped
                return False
            if ended and answered and time.time() >= settle:
                return True
            if time.time() >= deadline:
                return False
            time.sleep(STOP_PERIOD)


def connect(url, timeout):
    """ALMotion at ``url``, the connection waited for at most ``timeout`` [s]."""
    try:
        import qi
    except ImportError:
        try:
            from naoqi import ALProxy
        except ImportError:
            raise RuntimeError(
                "neither the qi package nor NAOqi's naoqi module is installed"
            )
        host, port = url.split("://")[-1].split(":")
        return Motion(ALProxy("ALMotion", host, int(port)))
    try:  # libqi's warning that no qi.Application was made: nothing wrong
        qi.logging.setFilters("-qi.path.sdklayout")
    except (AttributeError, RuntimeError):  # a qi without it
        pass
    session = qi.Session()
    for what, send in (
        ("connect to", lambda: session.connect(url, _async=True)),
        ("find ALMotion at", lambda: session.service("ALMotion", _async=True)),
    ):
        future = send()
        if not _wait(future.isFinished, timeout):
            future.cancel()
            raise RuntimeError(
                "cannot %s %s: no answer within %g s (--timeout SECONDS); nothing "
                "was sent" % (what, url, timeout)
            )
        if future.hasError():
            raise RuntimeError(
                "cannot %s %s: %s; nothing was sent"
                % (what, url, future.error().split("\\n")[0])
            )
    return Motion(future.value(), session)


def _seconds(text):
    import argparse

    value = float(text)
    if not 0 < value < 1e6:
        raise argparse.ArgumentTypeError("must be in (0, 1e6) s, got %r" % text)
    return value


def _robot_url(text):
    """``text`` if it looks like ``tcp://HOST:PORT``; else a usage error.

    Mirrors bridge/address.py's check_robot_url (its ``_URL`` pattern and
    port range) without ``re``: a malformed address is refused before
    anything connects, in the bridge's and the demo's words.
    """
    import argparse

    scheme, _, rest = text.partition("://")
    host, _, port = rest.rpartition(":")
    if (
        scheme not in ("tcp", "tcps")
        or not host
        or [c for c in host if c not in HOST_CHARACTERS]
        or not 1 <= len(port) <= 5
        or [c for c in port if c not in "0123456789"]
        or not 0 < int(port) < 65536
    ):
        raise argparse.ArgumentTypeError(
            "robot address %r must look like tcp://HOST:PORT "
            "(a real NAO: tcp://IP:9559)" % text
        )
    return text


def options(argv):
    """The parsed command line (``argparse`` exits 0 on --help, 2 on misuse)."""
    import argparse
    import os
    import sys

    parser = argparse.ArgumentParser(
        prog=os.path.basename(sys.argv[0]) or "play.py",
        description=(
            "Play the %s arm's trajectory (%d frames at %g fps, %.3f s; joints %s) "
            "on the NAO at URL: stiffen the joints where they are, move to the "
            "start within %g %% of their speed, acceleration and jerk limits, then "
            "play it. Ctrl-C (or "
            "SIGTERM) stops the arm where it is and exits 130 (143); a refusal, "
            "a robot not answering or a stalled call exits 1."
            % (ARM, FRAMES, RATE, DURATION, ", ".join(names), 100 * SPEED)
        ),
    )
    parser.add_argument(
        "url",
        nargs="?",
        default=URL,
        type=_robot_url,
        metavar="URL",
        help="the robot's NAOqi address (default %s)" % URL,
    )
    parser.add_argument(
        "--timeout",
        type=_seconds,
        default=CONNECT_TIMEOUT,
        metavar="SECONDS",
        help="longest wait for the robot to answer the connection (default %g)"
        % CONNECT_TIMEOUT,
    )
    return parser.parse_args(argv)


def _stopping(signum, frame):
    import signal

    if Stopped.raised:
        return
    Stopped.raised = True
    what = "terminated" if signum == signal.SIGTERM else "interrupted"
    what = "hung up" if signum == getattr(signal, "SIGHUP", None) else what
    raise Stopped(128 + signum, what)


def play(url, timeout):
    """Connect, stiffen, move to the start, play: (exit code, line or None)."""
    motion = None
    try:
        motion = connect(url, timeout)
        others = other_arm_parts(motion.getAngles(OTHER_JOINTS, True))
        check_clear(names, keys, times, "the trajectory", others, OTHER_ARM_ADVICE)
        stiffen_where_it_is(motion, names)
        motion.move_to(start, SPEED, others)
        motion.angleInterpolation(names, keys, times, True)
        ends = [joint_keys[-1] for joint_keys in keys]
        check_arrived(
            names,
            motion.getAngles(names, False),
            ends,
            "the trajectory",
            "its last key",
            "it was not played to its end",
        )
        return 0, None
    except (Stopped, Stalled) as error:
        Stopped.raised = True
        code = getattr(error, "code", 1)
        head = ("error: %s" if code == 1 else "%s") % error
        if motion is None or not motion.sent:
            return code, head + "; nothing was sent"
        if motion.stop():
            return code, head + "; the arm was stopped where it is"
        return code, head + (
            "; the robot did not confirm the stop (killTasksUsingResources) "
            "within %g s: the arm may still move" % STOP_WAIT
        )
    except RuntimeError as error:
        return 1, "error: %s" % error


def main(argv=None):
    """Run the script: the exit code. One line: on stdout what it played,
    else on stderr why not."""
    import os
    import signal
    import sys

    args = options(argv)
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), _stopping)
    code, line = play(args.url, args.timeout)
    if line:
        sys.stderr.write("%s: %s\\n" % (os.path.basename(sys.argv[0]), line))
    elif code == 0:
        frames = "%d frame%s" % (FRAMES, "" if FRAMES == 1 else "s")
        sys.stdout.write("played %s (%.3f s) on %s\\n" % (frames, DURATION, args.url))
    return code


if __name__ == "__main__":
    import sys

    sys.exit(main())
'''


def runner_source(
    arm: str, frames: int, rate: float, duration: float, speed: float
) -> str:
    """The runner's Python (2 and 3) for a script of ``frames`` keys.

    The keys come at ``rate`` [fps] and last ``duration`` [s]; the move to
    the start (``bridge.script_approach``) keeps within ``speed`` of the
    speed, acceleration and jerk limits. The text follows the script's
    lists and ``stiffen_where_it_is``.
    """
    return approach_source(arm) + _SOURCE.format(
        arm=arm,
        frames=frames,
        rate=rate,
        duration=round(duration, 6),
        speed=speed,
        connect_timeout=CONNECT_TIMEOUT,
        margin=MARGIN,
        poll=POLL,
        stop_wait=STOP_WAIT,
        stop_period=STOP_PERIOD,
        stop_settle=STOP_SETTLE,
    )
