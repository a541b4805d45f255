"""``armplan ik``: joint angles that put the wrist on a target."""

from __future__ import annotations

import argparse
import math
import sys

from armplan.cli.one_target import OneTarget
from armplan.cli.output import angle_text, print_json, print_table
from armplan.cli.palm_line import palm_line
from armplan.cli.parsing import (
    add_arm,
    add_json,
    add_measure_options,
    finite,
    measure_fields,
)
from armplan.cli.remote import add_remote, is_remote
from shared.messages import IKRequest, IKResult, Method, parse
from shared.robot import Side, load_arm

ORDER = 20
HELP = "inverse kinematics: joint angles that put the wrist on a target"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``ik``."""
    parser = commands.add_parser("ik", help=HELP, description=HELP)
    add_arm(parser)
    parser.add_argument(
        "--target",
        action=OneTarget,
        type=float,
        nargs=3,
        required=True,
        metavar=("X", "Y", "Z"),
        help="wrist target in the torso frame [m]",
    )
    parser.add_argument(
        "--primitive", help='movement primitive to use, e.g. "S_R E_PR W_P" (method mp)'
    )
    parser.add_argument(
        "--method",
        default="mp",
        choices=[m.value for m in Method],
        help="mp (the paper's method), least-norm or single (baselines)",
    )
    parser.add_argument(
        "--palm",
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="direction to turn the palm towards, torso frame: the wrist rolls "
        "about the forearm as far as that faces the palm to it (the forearm's "
        "direction comes from the target, so the palm can end off it; the "
        "answer says by how much)",
    )
    parser.add_argument(
        "--start",
        type=float,
        nargs=5,
        metavar="Q",
        help="start posture [rad] (default: arm hanging at rest)",
    )
    parser.add_argument(
        "--swivel",
        type=float,
        metavar="RAD",
        help=(
            "elbow swivel angle to move to, for S_R E_P W_R [rad] (pi: elbow "
            "down, 0: up; measured alike for both arms, so the left arm's "
            "mirror of a right-arm phi is 2*pi - phi; within two turns, 4*pi, "
            "of 0)"
        ),
    )
    add_measure_options(parser)
    add_json(parser)
    add_remote(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Solve (in-process, or by the IK service with --remote) and print it."""
    request = parse(
        IKRequest,
        {
            "arm": Side.parse(args.arm),  # any case, as the other commands
            "target": finite(args.target, "target"),
            "palm": finite(args.palm, "palm"),
            "primitive": args.primitive,
            "method": args.method,
            "start": finite(args.start, "start"),
            "swivel": args.swivel,
            "measures": measure_fields(args),
        },
    )
    result = _solve_remote(args, request) if is_remote(args) else _solve(request)
    if args.json:
        print_json(result.model_dump(mode="json"))
        return 0
    print_table(("joint", "angle [rad]"), _angle_rows(result))
    x, y, z = result.wrist
    sys.stdout.write(
        f"wrist ({x:.4f}, {y:.4f}, {z:.4f}) m, "
        f"{result.error * 1000:.3f} mm from the target; "
        f"method {result.method.value}"
        + (f", primitive {result.primitive}" if result.primitive else "")
        + "\n"
    )
    if result.palm_reached is not None:
        sys.stdout.write(palm_line(result.palm_reached) + "\n")
    if result.swivel_goal is not None and result.swivel_reached is not None:
        reached = nearest_turn(result.swivel_reached, result.swivel_goal)
        sys.stdout.write(
            f"elbow swivel {reached:.4f} rad reached "
            f"(asked {result.swivel_goal:.4f} rad)\n"
        )
    return 0


def nearest_turn(angle: float, near: float) -> float:
    """``angle`` [rad] plus the whole turns that bring it nearest ``near`` [rad].

    The swivel reached is in [0, 2 pi): asked 0, the left arm's came back as
    2 pi - 4e-9 and read "6.2832 rad reached (asked 0.0000 rad)", a turn off
    to the eye; asked 6.2832, 0.0000. Rounded to the printed digits (no -0).
    """
    turn = 2.0 * math.pi
    shifted = near + (angle - near + math.pi) % turn - math.pi
    return round(shifted, 4) + 0.0


def _angle_rows(result: IKResult) -> list[tuple[str, str]]:
    """(joint, angle [rad] as text) rows, each within its joint's range."""
    limits = load_arm(result.arm).limits
    rows = []
    for name, value in result.joints.items():
        k = limits.names.index(name)
        rows.append((name, angle_text(value, limits.lower[k], limits.upper[k])))
    return rows


def _solve(request: IKRequest) -> IKResult:
    from services.ik import solve_request

    return solve_request(load_arm(request.arm), request)


def _solve_remote(args: argparse.Namespace, request: IKRequest) -> IKResult:
    from armplan.cli.remote import connect
    from shared.bus.routes import IK_SOLVE

    with connect(args) as bus:
        return bus.call(IK_SOLVE, request)
