"""The robot side of a running armplan: the simulated NAO (optional) and the bridge.

``armplan up --with-sim`` and ``armplan demo`` start, after the router and
the services (:class:`~armplan.launch.launcher.Launcher`):

1. the simulated NAO (``python -m bridge.sim``, :class:`bridge.sim.SimProcess`),
   ready once it prints its NAOqi address; it stops by itself when this
   process ends (its stdin closes);
2. the bridge (``python -m bridge.serve --robot URL``) as a launcher child,
   ready once its liveliness token ``<ns>/alive/bridge`` is seen.

Without the sim the bridge connects to the robot the user named (``--robot
tcp://IP:9559`` or ``$ARMPLAN_ROBOT``). Stop order: the bridge, then the sim.
Example::

    with Launcher(config) as stack, RobotStack(config, sim=True) as robot:
        bus.call(EXECUTE, ExecuteRequest(trajectory=trajectory))
"""

from __future__ import annotations

import signal
import threading
import time
from pathlib import Path
from typing import IO, TYPE_CHECKING

from armplan.launch.bus_args import bus_args
from armplan.launch.catalog import BRIDGE
from armplan.launch.child import Child, stop_all
from armplan.launch.quoted_log import log_pointer
from shared.bus import Bus, BusConfig
from shared.errors import (
    InvalidInputError,
    RobotUnavailableError,
    ServiceUnavailableError,
)
from shared.lifecycle import StartStop
from shared.stop_signals import StartInterrupted

#: Longest wait for a stop request a signal sent, once the sim has failed [s]
#: (the relay thread sets it within milliseconds).
STOP_RELAY = 0.5

if TYPE_CHECKING:
    from bridge.sim import SimProcess

#: Longest wait for the sim, then for the bridge's token [s].
START_TIMEOUT = 60.0
#: Time the sim gets to exit after SIGTERM before SIGKILL [s].
GRACE = 5.0
#: Time the bridge gets to exit after SIGTERM before SIGKILL [s]: its own
#: bound on the wait for a trajectory still playing on a robot
#: (``bridge.stopping.STOP_LIMIT``, 30 s), the time to stop the arm of one
#: that plays longer and answer its caller (``bridge.stopping.CUT_WAIT``,
#: 1.25 s), the stops that follow a call still on its way until it ends
#: (``bridge.naoqi_client.RETIRE_AFTER``, 30 s, over a very slow link
#: only), and some to exit. Cut short, the arm would play on unwatched
#: and its caller get no answer.
BRIDGE_GRACE = 65.0
#: Pause between liveliness checks while starting [s].
POLL = 0.1
#: The sim's address for ``armplan up --with-sim``: a NAO's own port.
SIM_LISTEN = "tcp://127.0.0.1:9559"


class RobotStack(StartStop):
    """The bridge, and the simulated NAO it drives (if asked for).

    Attributes:
        config: The bus settings the bridge gets.
        url: The robot's NAOqi address, known once started.
        sim: The simulated NAO, if started.
        bridge: The bridge process, once started.
    """

    def __init__(
        self,
        config: BusConfig,
        *,
        robot: str | None = None,
        sim: bool = False,
        sim_listen: str = SIM_LISTEN,
        sim_log: str | Path | None = None,
        follow: bool = False,
        log: IO[str] | int | None = None,
        stop: threading.Event | None = None,
        allow_not_awake: bool = False,
    ) -> None:
        """Prepare (start nothing yet).

        Args:
            config: The bus settings (router endpoints, namespace, file).
            robot: A robot's NAOqi address (``tcp://IP:9559``); with ``sim``
                it must be ``None``.
            sim: Start the simulated NAO and point the bridge at it.
            sim_listen: Where the sim serves (port 0: any free port).
            sim_log: The sim's JSON-lines log file, or ``None``.
            follow: The bridge also plays every published trajectory.
            log: Where the bridge's output goes (as for ``Launcher``).
            stop: Set by a signal handler to abort a start in progress.
            allow_not_awake: The bridge plays even on a robot that is not
                awake (its ``--allow-not-awake``: a robot held up otherwise).

        Raises:
            InvalidInputError: ``robot`` and ``sim`` both given.
        """
        if sim and robot is not None:
            raise InvalidInputError(
                f"a robot address ({robot}) and the simulated NAO were both "
                "asked for: choose one",
                field="robot",
            )
        self.config = config
        self.url = robot or ""
        self.sim: SimProcess | None = None
        self.bridge: Child | None = None
        self._sim_wanted = sim
        self._sim_listen = sim_listen
        self._sim_log = sim_log
        self._follow = follow
        self._allow_not_awake = allow_not_awake
        self._log = log
        self._stop = stop or threading.Event()

    def start(self, timeout: float = START_TIMEOUT) -> RobotStack:
        """Start the sim (if asked for) and the bridge; return once both serve.

        Raises:
            RobotUnavailableError: the sim did not start.
            ServiceUnavailableError: the bridge exited or did not come alive.
            InvalidInputError: a malformed robot address.
            StartInterrupted: ``stop`` was set while the bridge started.
        """
        try:
            self.url = self._start_sim(timeout) if self._sim_wanted else self._named()
            self.start_bridge()
            self._wait_bridge(timeout)
        except BaseException:
            self.stop()
            raise
        return self

    def start_bridge(self) -> Child:
        """Start (or restart) the bridge to the robot at ``url``; does not wait."""
        self.bridge = Child.start(
            BRIDGE.name, BRIDGE.module, self._bridge_args(), self._log
        )
        return self.bridge

    def _named(self) -> str:
        from bridge.address import robot_url  # bridge loads libqi: only when used

        return robot_url(self.url or None)

    def _start_sim(self, timeout: float) -> str:
        from bridge.sim import SimProcess

        self.sim = SimProcess(
            listen=self._sim_listen, log_path=self._sim_log, startup_timeout=timeout
        )
        try:
            return self.sim.start()
        except RuntimeError as error:
            # a Ctrl-C to the terminal's group ends a sim still starting too:
            # that is the stop asked for, not a robot that failed
            if self._stop.wait(STOP_RELAY):
                raise StartInterrupted(getattr(self._stop, "signal", None)) from None
            raise RobotUnavailableError(self._sim_listen, str(error)) from None

    def _bridge_args(self) -> list[str]:
        args = [*bus_args(self.config), "--robot", self.url]
        if self._allow_not_awake:
            args.append("--allow-not-awake")
        return [*args, "--follow"] if self._follow else args

    def _wait_bridge(self, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        with Bus.connect(self.config) as bus:
            while missing := bus.wait_alive([BRIDGE.name], POLL):
                self._check_running()
                if time.monotonic() > deadline:
                    raise bus.not_alive(missing, timeout)

    def _check_running(self) -> None:
        if self._stop.is_set():
            raise StartInterrupted(getattr(self._stop, "signal", None))
        for name, pid, code in self.exited():
            raise ServiceUnavailableError(
                name,
                reason=f"its process {pid} exited with code {code} while starting "
                f"{log_pointer(self._log)}",
            )

    def processes(self) -> dict[str, int]:
        """The PID of each process started, by name (``sim``, ``bridge``)."""
        found = {}
        if self.sim is not None and self.sim.pid:
            found["sim"] = self.sim.pid
        if self.bridge is not None:
            found[BRIDGE.name] = self.bridge.pid
        return found

    def exited(self) -> list[tuple[str, int, int]]:
        """``(name, pid, exit code)`` of each started process no longer running."""
        gone = []
        if self.sim is not None and (code := self.sim.exit_code()) is not None:
            gone.append(("sim", self.sim.pid, code))
        if self.bridge is not None and (code := self.bridge.exit_code()) is not None:
            gone.append((BRIDGE.name, self.bridge.pid, code))
        return gone

    def stop(self, grace: float = GRACE, bridge_grace: float = BRIDGE_GRACE) -> None:
        """Stop the bridge and the sim (SIGTERM, SIGKILL after a grace [s]).

        Both get SIGTERM at once: a bridge that is playing a trajectory on the
        sim then sees the robot go and ends its request at once, instead of
        playing on while the stop waits for it. On a real robot the bridge
        watches a trajectory still playing to its end, so it gets
        ``bridge_grace`` (its own bound and some), the sim ``grace``.
        """
        if self.bridge is not None:
            self.bridge.signal(signal.SIGTERM)
        if self.sim is not None:
            self.sim.stop(grace)
        if self.bridge is not None:
            stop_all([self.bridge], bridge_grace)
