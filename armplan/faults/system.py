"""Every armplan process on a free loopback port, to be killed and restarted.

:class:`FaultSystem` starts what ``armplan demo`` starts
(:class:`~armplan.demo.stack.DemoStack`: the router, fit, decide, ik,
timing, planner, the simulated NAO, the bridge and the recorder), from its
own configuration file (a free ``127.0.0.1`` port, multicast scouting off,
a small payload limit), and knows each process by name. It kills one with
SIGKILL (remembering that it did), starts it again, and reports any process
that exited without being killed: a crash.
"""

from __future__ import annotations

import contextlib
import json
import signal
from pathlib import Path

from armplan.demo.stack import LOGS_DIR, RECORDING_FILE, DemoStack
from armplan.faults.out_folder import CONFIG_FILE, claim_out_folder
from armplan.launch import Launcher, free_endpoint
from armplan.launch.child import Child
from armplan.launch.robot import RobotStack
from services.recorder import RecorderOptions, RecorderProcess
from shared.bus import Bus, BusConfig, load_config
from shared.errors import InvalidInputError, RecordingError
from shared.lifecycle import StartStop
from shared.output_paths import make_output_folder

#: The namespace of the suite's keys (``faults/plan``).
NAMESPACE = "faults"
#: Largest request a service accepts in the suite [bytes] (1 MiB).
MAX_PAYLOAD = 1 << 20
#: A service's own wait for the services it calls (the planner's stages) [s].
INNER_TIMEOUT = 20.0
#: Longest wait for a killed process to be reaped [s].
REAP_TIMEOUT = 30.0
#: Longest wait for restarted processes to be alive again [s].
HEAL_TIMEOUT = 90.0
#: What the recorder's token is called.
RECORDER = "recorder"


def write_config(path: Path) -> BusConfig:
    """Write a loopback-only router configuration on a free port; its settings."""
    text = {
        "mode": "router",
        "listen": {"endpoints": [free_endpoint()]},
        "scouting": {"multicast": {"enabled": False}, "gossip": {"enabled": False}},
        "metadata": {
            "armplan": {
                "namespace": NAMESPACE,
                "max_payload": MAX_PAYLOAD,
                "timeout": INNER_TIMEOUT,
            }
        },
    }
    path.write_text(json.dumps(text, indent=2) + "\n")
    return load_config(path)


class FaultSystem(StartStop):
    """The whole system, started from a folder, with its processes by name.

    Attributes:
        out: The folder: configuration, logs, recordings.
        config: The bus every process uses.
        stack: The processes (router and services, sim and bridge, recorder).
    """

    def __init__(self, out: Path, *, overwrite: bool = False) -> None:
        """Prepare (start nothing yet); ``out`` is created if missing.

        Args:
            out: The folder for the configuration, the logs, the recordings.
            overwrite: Remove files an earlier run left there under the
                names the suite writes, instead of refusing the folder.

        Raises:
            InvalidInputError: ``out`` cannot be made, or holds such files
                and ``overwrite`` is false (naming them).
        """
        self.out = make_output_folder(out)
        claim_out_folder(out, overwrite)
        self.config = write_config(out / CONFIG_FILE)
        self.stack = DemoStack(self.config, out)
        self._killed: set[int] = set()
        self._reported: set[int] = set()
        self._recorders = 1
        self._exits = contextlib.ExitStack()

    @property
    def launcher(self) -> Launcher:
        """The router and the services."""
        assert self.stack.launcher is not None, "not started"
        return self.stack.launcher

    @property
    def robot(self) -> RobotStack:
        """The sim and the bridge."""
        assert self.stack.robot is not None, "not started"
        return self.stack.robot

    def names(self) -> list[str]:
        """Every process that holds a liveliness token, in start order."""
        return [n for n in self.stack.processes() if n not in ("router", "sim")]

    def pid(self, name: str) -> int:
        """The PID of process ``name`` now."""
        return self.stack.processes()[name]

    def running(self) -> dict[str, bool]:
        """Whether each process runs, by name."""
        gone = {c.name for c in self.launcher.exited()}
        gone |= {name for name, _, _ in self.robot.exited()}
        recorder = self.stack.recorder
        if recorder is not None and recorder.process.poll() is not None:
            gone.add(RECORDER)
        return {name: name not in gone for name in self.stack.processes()}

    def kill(self, name: str) -> int:
        """SIGKILL process ``name`` and reap it; its PID.

        Raises:
            InvalidInputError: no process of that name (the sim is not one:
                it is not on Zenoh).
        """
        recorder = self.stack.recorder
        if name == RECORDER and recorder is not None:
            self._killed.add(recorder.pid)
            recorder.kill()
            return recorder.pid
        child = self._child(name)
        self._killed.add(child.pid)
        child.signal(signal.SIGKILL)
        child.process.wait(REAP_TIMEOUT)
        return child.pid

    def _child(self, name: str) -> Child:
        if name == "router" and self.launcher.router is not None:
            return self.launcher.router
        if name == "bridge" and self.robot.bridge is not None:
            return self.robot.bridge
        if name in self.launcher.services:
            return self.launcher.services[name]
        known = ", ".join(n for n in self.stack.processes() if n != "sim")
        raise InvalidInputError(
            f"no process {name!r} to kill or restart; known: {known}", field="name"
        )

    def restart(self, name: str) -> int:
        """Start process ``name`` again (the recorder: into a new file); its PID.

        Returns at once, except for the recorder, which is ready on return.
        """
        if name == RECORDER:
            return self._restart_recorder()
        if name == "router":
            return self.launcher.start_router().pid
        if name == "bridge":
            return self.robot.start_bridge().pid
        self._child(name)  # a known service
        return self.launcher.start_service(name).pid

    def _restart_recorder(self) -> int:
        self._recorders += 1
        stem = Path(RECORDING_FILE).stem
        path = self.out / f"{stem}-{self._recorders}.mcap"
        log = self._exits.enter_context(
            (self.out / LOGS_DIR / f"recorder-{self._recorders}.log").open("a")
        )
        recorder = self._exits.enter_context(
            RecorderProcess.start(
                self.config, path, options=RecorderOptions(overwrite=True), log=log
            )
        )
        self.stack.recorder = recorder
        return recorder.pid

    def wait_alive(self, bus: Bus, timeout: float) -> list[str]:
        """Wait until every token-holding process is alive; those still missing."""
        return bus.wait_alive(self.names(), timeout)

    def crashes(self) -> list[str]:
        """``name (pid)`` of each process that exited unkilled since last asked."""
        found = []
        for name, up in self.running().items():
            pid = self.pid(name)
            if not up and pid not in self._killed | self._reported:
                self._reported.add(pid)
                found.append(f"{name} ({pid})")
        return found

    def heal(self, bus: Bus, timeout: float = HEAL_TIMEOUT) -> list[str]:
        """Restart every process that is down (not the sim); those still missing.

        A scenario that crashed a process leaves it down; the next one
        starts from a whole system.
        """
        down = [n for n, up in self.running().items() if not up and n != "sim"]
        for name in down:
            self.restart(name)
        return self.wait_alive(bus, timeout) if down else []

    def recordings(self) -> list[Path]:
        """The recorders' files, in the order they were started."""
        stem = Path(RECORDING_FILE).stem
        later = [self.out / f"{stem}-{n}.mcap" for n in range(2, self._recorders + 1)]
        return [self.out / RECORDING_FILE, *later]

    def start(self) -> FaultSystem:
        """Start every process; return once each one serves."""
        self.stack.start()
        return self

    def stop(self) -> None:
        """Stop every process: restarted recorders first, then the stack."""
        with contextlib.suppress(RecordingError):  # a recorder that had to be killed
            self._exits.close()
        self.stack.stop(settle=False)
