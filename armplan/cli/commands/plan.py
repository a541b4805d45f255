"""``armplan plan``: a human-like arm trajectory for a task.

    armplan plan --target X Y Z [--dwell S] [--palm X Y Z] [--hand open|close]
                 [--target ...]
                 [--arm right|left] [--method mp|least-norm|single]
                 [--fastest] [--rate HZ] [--start Q1..Q5] [--other-arm Q1..Q5]
                 [--max-acceleration A [A x4]] [--max-jerk J [J x4]]
                 [--model FILE] [--json]
    armplan plan --wrist-path FILE.csv [--arm ...] [--method ...]
                 [--start ...] [--palm X Y Z] [--json]
    armplan plan --task FILE.json [--method ...] [--fastest] [--rate HZ] [--json]

Targets are reached in order, one trajectory through all of them; ``--dwell``,
``--palm`` and ``--hand`` belong to the ``--target`` they follow
(:mod:`armplan.cli.plan_request`). With ``--wrist-path`` the joint angles come
at exactly the CSV's times, no retiming. ``--json`` prints the SPEC's
trajectory JSON; otherwise a table of every tenth sample and a summary
(:mod:`armplan.cli.plan_output`).

The command is three steps kept apart, so that the planner service can stand
in for the second: ``request_from_args`` (options to a ``PlanRequest``),
``plan_trajectory`` (the planning, here in-process; with ``--remote`` or
``--connect`` the planner service at ``<ns>/plan``) and ``show`` (output from
the request and the ``Trajectory`` message alone).
"""

from __future__ import annotations

import argparse

from armplan.cli.parsing import add_arm, add_json, add_measure_options
from armplan.cli.plan_output import show
from armplan.cli.plan_request import StepAction, request_from_args
from armplan.cli.remote import add_remote, check_timeout, is_remote
from shared.errors import InvalidInputError, RequestTimeoutError
from shared.messages import Method, MotionModel, PlanRequest, Trajectory
from shared.messages.hand import HandAction

ORDER = 27
HELP = "plan a human-like arm trajectory: targets, a timed wrist path, or a task"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``plan``."""
    parser = commands.add_parser("plan", help=HELP, description=HELP)
    add_arm(parser)
    parser.set_defaults(arm=None)  # None: right, or the task file's arm
    _add_task(parser)
    _add_per_target(parser)
    _add_how(parser)
    add_json(parser)
    add_remote(parser)
    parser.add_argument(
        "--timeout",
        type=float,
        metavar="S",
        help="with --remote: longest wait for the plan [s] (default: the "
        "config's timeout, 5)",
    )
    parser.set_defaults(run=run, steps=None)


def _add_task(parser: argparse.ArgumentParser) -> None:
    """What to do: targets, a wrist path or a task file (exactly one)."""
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument(
        "--target",
        dest="steps",
        action=StepAction,
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="wrist target in the torso frame [m]; repeat for more targets",
    )
    what.add_argument(
        "--wrist-path",
        metavar="FILE.csv",
        help="timed wrist path to follow at its own times (header t,x,y,z; s, m); "
        "the arm starts on its first sample (IK there from --start)",
    )
    what.add_argument("--task", metavar="FILE.json", help="a whole PlanRequest as JSON")


def _add_per_target(parser: argparse.ArgumentParser) -> None:
    """Options that belong to the ``--target`` before them."""
    parser.add_argument(
        "--dwell",
        dest="steps",
        action=StepAction,
        type=float,
        metavar="S",
        help="hold still this long at the target before it [s]",
    )
    parser.add_argument(
        "--palm",
        dest="steps",
        action=StepAction,
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="direction to turn the palm towards at the target before it (or "
        "along --wrist-path), torso frame: the wrist rolls about the forearm as "
        "far as that faces the palm to it (the forearm's direction comes from "
        "the target, so the palm can end off it; the summary says by how much)",
    )
    parser.add_argument(
        "--hand",
        dest="steps",
        action=StepAction,
        choices=[a.value for a in HandAction],
        help="open or close the hand at the target before it, during its dwell "
        "(lengthened to the hand's 0.45 s if shorter)",
    )


def _add_how(parser: argparse.ArgumentParser) -> None:
    """How to plan: method, pace, sample rate, start posture."""
    parser.add_argument(
        "--method",
        choices=[m.value for m in Method],
        help="mp (the paper's method, default), least-norm or single (baselines)",
    )
    parser.add_argument(
        "--fastest",
        action="store_true",
        help="as fast as a smooth profile along the path allows within the limits "
        "(not time-optimal) instead of at human pace",
    )
    parser.add_argument(
        "--rate",
        type=float,
        metavar="HZ",
        help="trajectory samples per second [Hz], 16 to 1000 (default 100; the "
        "robot refuses coarser samples); the duration is rounded up to whole "
        "sample periods, so a low rate can lengthen it",
    )
    parser.add_argument(
        "--path-tolerance",
        type=float,
        metavar="M",
        help="with --wrist-path: farthest the wrist may be from a sample [m] "
        "(default 0.001); a path the arm cannot follow that closely is refused",
    )
    parser.add_argument(
        "--start",
        type=float,
        nargs=5,
        metavar="Q",
        help="start posture [rad] (default: arm hanging at rest)",
    )
    parser.add_argument(
        "--other-arm",
        type=float,
        nargs=5,
        metavar="Q",
        help="where the other arm is held while this one moves [rad], its five "
        "joints: the plan keeps clear of it as of NAO's body (default: not "
        "known to the planner; the robot bridge keeps clear of it as measured)",
    )
    _add_limits(parser)
    add_measure_options(parser)
    parser.add_argument(
        "--model",
        metavar="FILE",
        help="motion model to decide with, from 'armplan fit -o' (default: the "
        "shipped one; in-process only: the services use the fit service's)",
    )


def _add_limits(parser: argparse.ArgumentParser) -> None:
    """The timing's acceleration and jerk limits (``TimingLimits``)."""
    parser.add_argument(
        "--max-acceleration",
        type=float,
        nargs="+",
        metavar="A",
        help="acceleration limit [rad/s^2]: one for every joint or five, "
        "ShoulderPitch to WristYaw (default: speed limit / 0.25 s; at most "
        "speed limit / 0.1 s, the bridge's safety net)",
    )
    parser.add_argument(
        "--max-jerk",
        type=float,
        nargs="+",
        metavar="J",
        help="jerk limit [rad/s^3]: one or five (default: the acceleration limit "
        "/ 0.05 s; at most the safety net's, speed limit / 0.1 s / 0.05 s)",
    )


def run(args: argparse.Namespace) -> int:
    """Build the request, plan it (here, or by the planner with --remote), print."""
    remote = is_remote(args)
    if not remote and args.timeout is not None:
        raise InvalidInputError(
            "--timeout goes with --remote (the running planner service)",
            field="timeout",
        )
    check_timeout(args.timeout)
    if remote and args.model:
        raise InvalidInputError(
            "--model does not go with --remote: the planner decides with the "
            "model the fit service serves (start it with 'armplan up --model')",
            field="model",
        )
    model = _model(args.model)  # a bad file is refused before any planning
    request = request_from_args(args)
    trajectory = (
        _plan_remote(args, request) if remote else plan_trajectory(request, model)
    )
    show(request, trajectory, args.json)
    return 0


def plan_trajectory(
    request: PlanRequest, model: MotionModel | None = None
) -> Trajectory:
    """Plan ``request`` in this process (``services.planner.pipeline.plan``).

    ``model``: the motion model to decide with; default the shipped one.
    """
    from services.planner.pipeline import plan
    from services.planner.stages import LocalStages

    stages = None if model is None else LocalStages(model)
    return plan(request, stages).trajectory


def _model(path: str | None) -> MotionModel | None:
    """The ``--model`` file's model, or ``None``.

    Raises:
        ModelFileError: naming the file: unreadable, or a model the decision
            cannot use (``services.fit.decidable``).
    """
    if path is None:
        return None
    from services.fit.decidable import load_decidable

    return load_decidable(path)


def _plan_remote(args: argparse.Namespace, request: PlanRequest) -> Trajectory:
    """Plan ``request`` with the planner service (``armplan/plan``).

    Each run is a new request: it gets a fresh ``request_id``, also when a
    ``--task`` file carries one (say, copied from a recording), which would
    otherwise get that request's answer, neither planned nor published again.
    """
    from armplan.cli.remote import connect
    from shared.bus.routes import PLAN
    from shared.messages.request_id import with_new_request_id

    with connect(args) as bus:
        try:
            return bus.call(
                PLAN, with_new_request_id(request), timeout=args.timeout, repeat=True
            )
        except RequestTimeoutError as error:
            if error.key != PLAN.key(bus.config.namespace):
                raise  # a stage's, relayed: the planner waits it the config's
            waited = bus.config.timeout if args.timeout is None else args.timeout
            error.message += (
                f"; a long task or a busy planner takes longer: give a longer "
                f"--timeout (this call waited {waited:g} s)"
            )
            raise
