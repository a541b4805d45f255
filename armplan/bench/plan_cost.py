"""Planning a one-second reach in-process, beside peers doing the same work.

The reach: the service benchmark's one-second reach
(:func:`armplan.bench.service_latency.one_second_reach`: the paper's grid
point 13 from the hanging right arm, a 1.0 s trajectory from a wrist path of
96 points at 100 Hz), so in-process figures compare across both. Ours is
``services.planner.pipeline.plan`` end to end, request in, ``Trajectory``
message out, with method ``mp`` and with each baseline. The peers, on the
same reach in the same run:

- toppra: the time-optimal parameterisation of the same joint path (the
  ``mp`` plan's, before timing), sampled at 100 Hz
  (:func:`armplan.bench.timing_cost.toppra_trajectory`);
- ikpy: the IK of the same wrist points (:mod:`armplan.bench.ikpy_peer`).

A peer does less than a whole plan, so it is also set beside the part of
ours doing its work (:mod:`armplan.bench.plan_parts`): toppra beside our
timing, ikpy beside our IK tracking. Figures are medians over the repeats,
timed in rounds (every plan, toppra and every part once per round) so a
change of the machine's load slows them alike; ikpy's passes come after.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from functools import partial
from typing import NamedTuple

import numpy as np

from armplan.bench import ikpy_peer
from armplan.bench.extras import require
from armplan.bench.plan_parts import PARTS, PlanParts, part_calls
from armplan.bench.service_latency import one_second_reach
from armplan.bench.timer import Timing, time_calls, time_rounds
from armplan.bench.timing_cost import toppra_trajectory
from services.planner.build import arc_length
from services.planner.pipeline import plan
from services.timing import time_path
from shared.messages import Method, PlanRequest, parse
from shared.robot import load_arm, motion_limits
from shared.robot.postures import rest


class PlanCost(NamedTuple):
    """Results of the planning benchmark.

    Attributes:
        points: Wrist-path points of the reach.
        duration: Duration of the ``mp`` trajectory (human pace) [s].
        plans: Per method, time per ``plan`` call [s].
        toppra: Time per toppra parameterisation of the joint path [s].
        ikpy: Time per ikpy pass over the path's points [s].
        ikpy_reached: Fraction of points ikpy reached within 0.1 mm.
        parts: Our plan's parts, each timed on its own.
        toppra_duration: Duration of toppra's time-optimal trajectory [s].
        fastest_duration: Duration of our fastest timing of the path, by the
            hand's arc length as the planner times it (the timed part) [s].
        tracking_error: Our IK tracking's largest wrist error on the path [m].
        ikpy_error: ikpy's largest wrist error on the path's points [m].
        load_average: The machine's 1-minute load average at the start and
            the end of the run (runnable processes; compare with its CPUs).
    """

    points: int
    duration: float
    plans: dict[Method, Timing]
    toppra: Timing
    ikpy: Timing
    ikpy_reached: float
    parts: PlanParts
    toppra_duration: float
    fastest_duration: float
    tracking_error: float
    ikpy_error: float
    load_average: tuple[float, float] = (0.0, 0.0)

    def plan_time(self, method: Method = Method.MP) -> float:
        """Median time to plan the reach with ``method`` [s]."""
        return self.plans[method].percentile(50)

    def figures(self) -> dict[str, float]:
        """The JSON figures of ``armplan bench``: times [ms, us], ratios."""
        parts = self.parts
        figures = {
            "plan_points": float(self.points),
            "plan_duration_s": self.duration,
            "plan_load_average_start": self.load_average[0],
            "plan_load_average_end": self.load_average[1],
        }
        for method in Method:
            key = method.value.replace("-", "_")
            figures[f"plan_{key}_ms"] = self.plan_time(method) * 1e3
        figures |= {
            "toppra_ms": self.peer_time("toppra") * 1e3,
            "ikpy_ms": self.peer_time("ikpy") * 1e3,
            "ikpy_reached_fraction": self.ikpy_reached,
            "toppra_over_plan": self.peer_time("toppra") / self.plan_time(),
            "ikpy_over_plan": self.peer_time("ikpy") / self.plan_time(),
            "toppra_over_timing": self.peer_time("toppra")
            / parts.median("timing_fastest"),
            "toppra_duration_s": self.toppra_duration,
            "timing_fastest_duration_s": self.fastest_duration,
            "tracking_max_error_mm": self.tracking_error * 1e3,
            "ikpy_max_error_mm": self.ikpy_error * 1e3,
            "ikpy_over_tracking": self.peer_time("ikpy") / parts.median("tracking"),
            "ik_tracking_per_point_us": parts.tracking_per_point * 1e6,
            "decision_per_point_us": parts.decision_per_point * 1e6,
        }
        for name in PARTS:
            figures[f"part_{name}_ms"] = parts.median(name) * 1e3
        return figures

    def peer_time(self, peer: str) -> float:
        """Median time of ``"toppra"`` or ``"ikpy"`` on the reach [s]."""
        timing: Timing = getattr(self, peer)
        return timing.percentile(50)


def _largest_error(reached: object, points: np.ndarray) -> float:
    """Largest distance [m] between the wrists reached and the path's points."""
    return float(np.linalg.norm(np.asarray(reached) - points, axis=1).max())


def steps(repeats: int, ikpy_passes: int) -> int:
    """How many timed calls ``run`` makes (for a progress bar)."""
    return repeats * (len(Method) + 1 + len(PARTS)) + ikpy_passes


def run(
    repeats: int = 20,
    ikpy_passes: int = 1,
    after: Callable[[], object] | None = None,
    reach: PlanRequest | None = None,
) -> PlanCost:
    """Time ours (every method), toppra and ikpy on the one-second reach.

    Args:
        repeats: Timed calls of each plan, of toppra and of each part.
        ikpy_passes: Timed ikpy passes over the path (each solves every point,
            and takes seconds).
        after: Called after each timed call, untimed (progress).
        reach: Another reach to time instead (one target, from rest).
    """
    require("toppra", "ikpy")
    load_start = os.getloadavg()[0]
    reach = reach or one_second_reach()
    arm = load_arm(reach.arm)
    requests = {
        m: parse(PlanRequest, reach.model_dump() | {"method": m}) for m in Method
    }
    first = plan(requests[Method.MP])  # also compiles the motion model once
    joint_path = np.array(first.joint_paths[0].positions)
    points = np.array(first.wrist_paths[0].positions)
    limits = motion_limits(arm.limits)
    chain = ikpy_peer.wrist_chain(arm)
    solved: list[np.ndarray] = []
    calls: dict[str, Callable[[], object]] = {
        m.value: partial(plan, r) for m, r in requests.items()
    }
    calls["toppra"] = partial(toppra_trajectory, joint_path, limits)
    count, parts = part_calls(arm, reach.targets[0])
    calls |= {f"part_{name}": call for name, call in parts.items()}
    timings = time_rounds(calls, repeats, after)  # interleaved: load hits all alike
    ikpy = time_calls(
        [lambda: solved.append(ikpy_peer.ikpy_track(chain, points, rest(arm.side)))]
        * ikpy_passes,
        after,
    )
    return PlanCost(
        points=len(points),
        duration=first.trajectory.duration,
        plans={m: timings[m.value] for m in Method},
        toppra=timings["toppra"],
        ikpy=ikpy,
        ikpy_reached=ikpy_peer.reached_fraction(chain, solved[-1], points),
        parts=PlanParts(count, {name: timings[f"part_{name}"] for name in PARTS}),
        toppra_duration=toppra_trajectory(joint_path, limits)[0],
        fastest_duration=time_path(
            joint_path, limits, parameter=arc_length(first.joint_paths[0].wrist)
        ).duration,
        tracking_error=_largest_error(first.joint_paths[0].wrist, points),
        ikpy_error=_largest_error([arm.fk(q).wrist for q in solved[-1]], points),
        load_average=(load_start, os.getloadavg()[0]),
    )
