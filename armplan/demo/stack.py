"""Every process of the demo, started in order and stopped for sure.

Start order: the Zenoh router and every service (``Launcher``), the
simulated NAO and the bridge (``RobotStack``), then the recorder
(``RecorderProcess``), so that the recording holds the whole session from
the first plan on. Stop order is the reverse: the recorder closes its file
first, then the bridge and the sim, then the services and the router. Each
process also ends itself if the demo dies (``ARMPLAN_PARENT_PID``, the sim's
closed stdin), so not even a killed demo leaves one behind. A recording
that failed (the recorder exited with an error, or was killed) does not
stop the others from stopping: ``recording_error`` keeps why, for the run
to report.
"""

from __future__ import annotations

import contextlib
import signal
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from signal import SIGHUP, SIGINT, SIGTERM
from types import TracebackType
from typing import IO

from armplan.launch import Launcher
from armplan.launch.robot import RobotStack
from services.recorder import RecorderOptions, RecorderProcess
from shared.bus import BusConfig
from shared.errors import ArmplanError, RecordingError, error_from_wire

#: The recording, in the demo's folder.
RECORDING_FILE = "session.mcap"
#: The simulated NAO's log (JSON lines), in the demo's folder.
SIM_LOG_FILE = "sim.jsonl"
#: The processes' own logs, in the demo's folder.
LOGS_DIR = "logs"
#: The logs the demo's processes write there (``<name>.log``).
LOG_NAMES = ("services", "bridge", "recorder")
#: What a process's start failure says about its output.
SEE_LOG = "see its log"
#: Wait for the last publications to reach the recorder before stopping it [s].
SETTLE = 0.5


class DemoStack:
    """Router, services, robot side and recorder for one demo run.

    Attributes:
        config: The bus every process uses.
        out: The demo's folder.
        launcher: The router and the services, once started.
        robot: The sim (if simulated) and the bridge, once started.
        recorder: The recorder, once started (``None`` when not recording).
        recording_error: Why the recording failed, once the recorder is
            stopped (``None``: its file is whole, or nothing was recorded).
    """

    def __init__(
        self,
        config: BusConfig,
        out: Path,
        *,
        robot: str | None = None,
        record: bool = True,
        stop: threading.Event | None = None,
        allow_not_awake: bool = False,
    ) -> None:
        """Prepare (start nothing yet).

        Args:
            config: The bus settings (a free loopback endpoint by default).
            out: The folder for the recording and the logs.
            robot: A real NAO's address; ``None`` starts the simulated NAO.
            record: Record the session to ``out/session.mcap``.
            stop: Set by a signal handler to abort a start in progress.
            allow_not_awake: The bridge plays even on a robot that is not
                awake (its ``--allow-not-awake``).
        """
        self.config = config
        self.out = out
        self.launcher: Launcher | None = None
        self.robot: RobotStack | None = None
        self.recorder: RecorderProcess | None = None
        self.recording_error: RecordingError | None = None
        self._robot_url = robot
        self._record = record
        self._stop = stop
        self._allow_not_awake = allow_not_awake
        self._exits = contextlib.ExitStack()

    @property
    def simulated(self) -> bool:
        """True if the robot is the simulated NAO."""
        return self._robot_url is None

    def start(self) -> DemoStack:
        """Start every process; return once each one serves (or raise, stopped)."""
        logs = self.out / LOGS_DIR
        logs.mkdir(parents=True, exist_ok=True)
        with self._exits as exits:
            with _naming_log(self._log_path("services")):
                self.launcher = exits.enter_context(
                    Launcher(
                        self.config,
                        log=self._log("services"),
                        stop=self._stop,
                        # the shipped model, whatever a fit left in the cwd
                        service_args={"fit": ["--state-dir", str(logs)]},
                    )
                )
            with _naming_log(self._log_path("bridge")):
                self.robot = exits.enter_context(self._robot_stack())
            if self._record:
                with _naming_log(self._log_path("recorder")):
                    self.recorder = self._recorder()
                exits.callback(self._stop_recorder, self.recorder)
            self._exits = exits.pop_all()  # started: keep them running
        return self

    def _robot_stack(self) -> RobotStack:
        return RobotStack(
            self.config,
            robot=self._robot_url,
            sim=self.simulated,
            sim_listen="tcp://127.0.0.1:0",
            sim_log=self.out / SIM_LOG_FILE if self.simulated else None,
            log=self._log("bridge"),
            stop=self._stop,
            allow_not_awake=self._allow_not_awake,
        )

    def _recorder(self) -> RecorderProcess:
        log = self._log("recorder")
        return RecorderProcess.start(
            self.config,
            self.out / RECORDING_FILE,
            options=RecorderOptions(overwrite=True),  # the demo's folder is its own
            log=log,
        )

    def _stop_recorder(self, recorder: RecorderProcess) -> None:
        """Stop ``recorder``; if its recording failed, keep why (not raised).

        The processes started before it still stop, and an error that
        ended the run is not replaced by the recording's.
        """
        try:
            recorder.stop()
        except RecordingError as error:
            self.recording_error = error

    def _log_path(self, name: str) -> Path:
        """The log file of ``name``'s processes: ``out/logs/<name>.log``."""
        return self.out / LOGS_DIR / f"{name}.log"

    def _log(self, name: str) -> IO[str]:
        """The log file ``out/logs/<name>.log``, closed when the stack stops."""
        path = self._log_path(name)
        return self._exits.enter_context(path.open("a", encoding="utf-8"))

    def processes(self) -> dict[str, int]:
        """The PID of every process started, by name, in start order."""
        found: dict[str, int] = {}
        if self.launcher is not None:
            found.update({c.name: c.pid for c in self.launcher.children()})
        if self.robot is not None:
            found.update(self.robot.processes())
        if self.recorder is not None:
            found["recorder"] = self.recorder.pid
        return found

    def stop(self, settle: bool = True) -> None:
        """Stop everything: recorder, bridge and sim, services and router.

        Args:
            settle: Give the last publications :data:`SETTLE` seconds to
                reach the recorder first (not after a failure or Ctrl-C).

        A second Ctrl-C meanwhile is ignored, so the stop is never cut short
        (each process gets a bounded grace, then SIGKILL).
        """
        with _signals_held():
            if settle and self.recorder is not None:
                time.sleep(SETTLE)
            self._exits.close()

    def __enter__(self) -> DemoStack:
        return self.start()

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.stop(settle=kind is None)


@contextlib.contextmanager
def _naming_log(path: Path) -> Iterator[None]:
    """A start failure that says "see its log" also says where: ``path``.

    The error keeps its kind and evidence (plus ``log``); only its words
    gain the path, e.g. "... while starting (see its log demo/logs/services.log)".
    """
    try:
        yield
    except ArmplanError as error:
        if SEE_LOG not in error.message:
            raise
        named = f"{SEE_LOG} {path}"
        evidence = {
            key: value.replace(SEE_LOG, named) if isinstance(value, str) else value
            for key, value in error.evidence.items()
        }
        wire = {
            "kind": error.kind,
            "message": error.message.replace(SEE_LOG, named),
            "evidence": {**evidence, "log": str(path)},
        }
        raise error_from_wire(wire) from None


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Ignore SIGINT, SIGTERM and SIGHUP inside (main thread only; restored after)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held = {s: signal.signal(s, signal.SIG_IGN) for s in (SIGINT, SIGTERM, SIGHUP)}
    try:
        yield
    finally:
        for signum, handler in held.items():
            signal.signal(signum, handler)
