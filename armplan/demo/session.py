"""One run of the demo: start everything, plan, execute, write, stop.

:func:`run_demo` is ``armplan demo`` without its command line:

1. the task file is read and the task planned in this process
   (:mod:`armplan.demo.task_plan`): a bad one, a target the IK cannot reach
   or a task too long fails before anything starts, naming the file and
   the phase;
2. every process starts (:class:`~armplan.demo.stack.DemoStack`);
3. the task is planned by the planner service (``<ns>/plan``), which calls
   decide, ik and timing and publishes each part, and its exports' frames
   are checked (a behavior whose curve breaks a limit stops the demo
   here, before anything moves);
4. the trajectory is played through the bridge (``<ns>/bridge/execute``) on
   the simulated NAO (or the NAO named), which answers with the tracking
   report;
5. the files are written (:mod:`armplan.demo.outputs`) and every process is
   stopped, the recorder first, also when a step fails or on Ctrl-C. A
   recording that failed (disk full, the recorder killed) leaves the other
   files as they are: the result says why it failed, for the caller to
   report (``armplan demo`` exits 1).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from armplan.demo.earlier_run import replace_earlier_run
from armplan.demo.folder_claim import claimed_folder
from armplan.demo.outputs import (
    BEHAVIOR_FILE,
    PYTHON_FILE,
    REPORT_FILE,
    TRAJECTORY_FILE,
    Execution,
    export_frames,
    write_outputs,
)
from armplan.demo.stack import (
    LOG_NAMES,
    LOGS_DIR,
    RECORDING_FILE,
    SIM_LOG_FILE,
    DemoStack,
)
from armplan.demo.task import DEFAULT_TASK, Task, load_task
from armplan.demo.task_plan import check_task_plans
from bridge.choregraphe import timeline_fps
from bridge.frames import DEFAULT_RATE
from shared.bus import Bus, BusConfig
from shared.bus.robot_routes import EXECUTE
from shared.bus.routes import PLAN
from shared.errors import RecordingError
from shared.messages import ExecuteReply, ExecuteRequest, Trajectory
from shared.messages.request_id import with_request_id
from shared.output_paths import check_output_folder

#: Longest wait for the planner's answer [s].
PLAN_TIMEOUT = 60.0
#: Time allowed beyond the trajectory's duration for the approach move and
#: the reply [s]; a robot lost on the way is reported within 2 s anyway.
EXECUTE_MARGIN = 30.0
#: The files a run writes (or whose processes write them), relative to its
#: folder: an earlier run's are removed first, so that a failed run never
#: leaves them behind (:mod:`armplan.demo.earlier_run`).
OUTPUTS = (
    TRAJECTORY_FILE,
    BEHAVIOR_FILE,
    PYTHON_FILE,
    REPORT_FILE,
    RECORDING_FILE,
    SIM_LOG_FILE,
    *(f"{LOGS_DIR}/{name}.log" for name in LOG_NAMES),
)

Say = Callable[[str], None]


@dataclass(frozen=True)
class DemoOptions:
    """How to run the demo.

    Attributes:
        config: The bus (router endpoint, namespace).
        out: The folder to write into.
        task: The task file.
        robot: A real NAO's address; ``None``: the simulated NAO.
        record: Record the session to MCAP.
        rate: Frame rate of the command frames [Hz], a whole number (the
            timeline of ``behavior.xar`` has no other).
        allow_not_awake: The bridge plays even on a robot that is not awake
            (its ``--allow-not-awake``).
    """

    config: BusConfig
    out: Path = Path("armplan-demo")
    task: Path = DEFAULT_TASK
    robot: str | None = None
    record: bool = True
    rate: float = DEFAULT_RATE
    allow_not_awake: bool = False


@dataclass
class DemoResult:
    """What a run produced.

    Attributes:
        execution: The task, trajectory and the bridge's reply.
        files: The written files by name (``trajectory``, ``choregraphe``,
            ``python``, ``report``, ``recording``, ``sim_log``).
        processes: The PID of every process the run started, by name.
        recording_error: Why the recording failed (its file lacks its
            summary and may miss most of the session), or ``None``.
    """

    execution: Execution
    files: dict[str, Path] = field(default_factory=dict)
    processes: dict[str, int] = field(default_factory=dict)
    recording_error: RecordingError | None = None


def plan_task(bus: Bus, task: Task) -> Trajectory:
    """The task's trajectory from the planner service (``<ns>/plan``)."""
    request = with_request_id(task.plan_request())
    return bus.call(PLAN, request, timeout=PLAN_TIMEOUT, repeat=True)


def execute(bus: Bus, trajectory: Trajectory, rate: float) -> ExecuteReply:
    """Play ``trajectory`` through the bridge (``<ns>/bridge/execute``)."""
    request = ExecuteRequest(trajectory=trajectory, rate=rate)
    timeout = trajectory.duration + EXECUTE_MARGIN
    return bus.call(EXECUTE, request, timeout=timeout)


def run_demo(
    options: DemoOptions, say: Say, stop: threading.Event | None = None
) -> DemoResult:
    """Run the whole demo; ``say`` gets each progress line.

    Raises:
        InvalidInputError: ``options.out`` cannot be a folder, another
            demo is writing into it, it holds a file of an output's name
            that no earlier demo wrote, the task file is bad or its task
            cannot be planned (naming the phase and target), or the frame
            rate is no whole number (``behavior.xar`` needs one), all before
            anything starts.
        ArmplanError: a step failed (everything started is stopped first;
            a recording that failed too is said through ``say``).
    """
    timeline_fps(options.rate, "the demo's frame rate")
    check_output_folder(options.out)
    task = load_task(options.task)
    check_task_plans(task, options.task)  # a target the IK misses, too long
    with claimed_folder(options.out):
        return _run_in(options, task, say, stop)


def _run_in(
    options: DemoOptions, task: Task, say: Say, stop: threading.Event | None
) -> DemoResult:
    """``run_demo`` in its claimed output folder."""
    replace_earlier_run(options.out, OUTPUTS)
    stack = DemoStack(
        options.config,
        options.out,
        robot=options.robot,
        record=options.record,
        stop=stop,
        allow_not_awake=options.allow_not_awake,
    )
    say(f"starting the router, the services, the bridge and the {_robot(options)}")
    try:
        with stack:
            processes = stack.processes()
            say("running: " + ", ".join(f"{n} (pid {p})" for n, p in processes.items()))
            run = _play(stack, task, options, say)
            files = write_outputs(options.out, run)
    except BaseException:
        if stack.recording_error is not None:  # not to be lost behind the error
            say(f"the recording failed too: {stack.recording_error.message}")
        raise
    files = {**files, **_process_files(options)}
    return DemoResult(run, files, processes, stack.recording_error)


def _play(stack: DemoStack, task: Task, options: DemoOptions, say: Say) -> Execution:
    """Plan through the planner service, then play through the bridge."""
    assert stack.robot is not None
    with Bus.connect(options.config) as bus:
        trajectory = plan_task(bus, task)
        frames = export_frames(trajectory, options.rate)  # before anything moves
        say(
            f"planned through {PLAN.key(options.config.namespace)}: "
            f"{trajectory.duration:.2f} s, {len(trajectory.times)} samples; "
            f"playing it through {EXECUTE.key(options.config.namespace)}"
        )
        reply = execute(bus, trajectory, options.rate)
    robot = stack.robot.url
    return Execution(
        task, trajectory, reply, robot, stack.simulated, options.rate, frames
    )


def _process_files(options: DemoOptions) -> dict[str, Path]:
    """The files the processes wrote: recording, the sim's log, the logs."""
    files = {}
    if options.record:
        files["recording"] = options.out / RECORDING_FILE
    if options.robot is None:
        files["sim_log"] = options.out / SIM_LOG_FILE
    return {**files, "logs": options.out / LOGS_DIR}


def _robot(options: DemoOptions) -> str:
    return "simulated NAO" if options.robot is None else f"NAO at {options.robot}"
