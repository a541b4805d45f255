"""The tables ``armplan bench`` prints: each figure beside its peer's, as a ratio.

Every function takes the flat figures of ``--json`` (times [ms, us], rates
[1/s], ratios) so the table and the JSON can never disagree. A figure with
nothing to measure (NaN: the IK beside SLSQP on the targets both reached,
when SLSQP reached none) prints as ``-``, as ``--json`` gives ``null``.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from typing import Any

from armplan.bench.service_latency import PER_CLIENT
from armplan.cli.output import print_table
from shared.text.counted import counted

#: The bars the issues set [ms]: a one-second reach planned in-process, and
#: through the services on loopback (p50).
IN_PROCESS_BAR_MS = 10.0
SERVICES_BAR_MS = 20.0

Figures = dict[str, float]

#: The row setting toppra beside our ``--fastest`` timing: the nearest part of
#: ours, not the same problem (ours: a jerk-limited bell stretched until it
#: first touches a limit; toppra: time-optimal under speed and acceleration
#: limits alone, riding them), so their trajectories' durations follow it.
UNLIKE_TIMING = "Ruckig --fastest vs toppra (unlike work)"


def print_machine(f: Figures, processor: str) -> None:
    """The machine: processor, CPUs and the 1-minute load average over the run."""
    sys.stdout.write(
        f"machine: {processor}, {f['cpus']:.0f} CPUs, 1-minute load average "
        f"{f['load_average_start']:.2f} -> {f['load_average_end']:.2f} "
        "over the run; the IK's hot loop "
        + ("compiled (mypyc)" if f.get("compiled") else "ran as Python (not compiled)")
        + "\n\n"
    )


def print_ik(f: Figures) -> None:
    """The IK per target beside scipy SLSQP (same measure) and ikpy (position)."""
    targets = counted(round(f["targets"]), "random reachable target")
    sys.stdout.write(f"IK of {targets}, means:\n")
    ours = f["ik_per_target_ms"]
    _table(
        ("measure", "armplan", "peer", "peer / armplan"),
        [
            ("IK per target vs scipy SLSQP [ms]", ours, f["slsqp_per_target_ms"],
             f["speedup_vs_slsqp"]),
            (f"  on the {f['common_targets']:.0f} both reached [ms]",
             f["ik_per_common_target_ms"], f["slsqp_per_common_target_ms"],
             f["speedup_vs_slsqp_on_common"]),
            ("IK per target vs ikpy [ms]", ours, f["ikpy_per_target_ms"],
             f["speedup_vs_ikpy"]),
            ("reached within 0.1 mm, SLSQP", f["ik_reached_fraction"],
             f["slsqp_reached_fraction"], "-"),
            ("reached within 0.1 mm, ikpy", f["ik_reached_fraction"],
             f["ikpy_ik_reached_fraction"], "-"),
            ("TPE ours - SLSQP, both reached [J]",
             f["tpe_gap_on_common_targets_j"], "-", "-"),
            ("one eq. 14 step, 20 in a row [us]", f["gpm_step_per_point_us"],
             "-", "-"),
        ],
    )  # fmt: skip


def print_planning(f: Figures) -> None:
    """The one-second reach: whole plans beside the peers, then the parts."""
    plan, timing = f["plan_mp_ms"], f["part_timing_fastest_ms"]
    tracking = f["part_tracking_ms"]
    sys.stdout.write(
        f"\none-second reach in-process ({f['plan_points']:.0f} path points, a "
        f"{f['plan_duration_s']:.2f} s trajectory), medians [ms]:\n"
    )
    _table(
        ("measure", "armplan", "peer", "peer / armplan"),
        [
            ("plan, method mp", plan, "-", "-"),
            ("plan, least-norm baseline", f["plan_least_norm_ms"], "-", "-"),
            ("plan, single baseline", f["plan_single_ms"], "-", "-"),
            _versus("whole plan vs toppra timing", plan, f, "toppra", "plan"),
            _versus("whole plan vs ikpy IK", plan, f, "ikpy", "plan"),
            _versus(UNLIKE_TIMING, timing, f, "toppra", "timing"),
            (
                "  trajectories [s]: our jerk-limited bell, toppra's time-optimal",
                f["timing_fastest_duration_s"],
                f["toppra_duration_s"],
                "-",
            ),
            _versus("IK tracking vs ikpy", tracking, f, "ikpy", "tracking"),
            (
                "  largest wrist error [mm]",
                f["tracking_max_error_mm"],
                f["ikpy_max_error_mm"],
                "-",
            ),
            ("ikpy: points within 0.1 mm", "-", f["ikpy_reached_fraction"], "-"),
        ],
    )
    sys.stdout.write("\nparts of the mp plan, each timed alone:\n")
    _table(
        ("part", "median [ms]", "per path point [us]"),
        [
            ("wrist path", f["part_wrist_path_ms"], "-"),
            ("decision + IK tracking", f["part_decide_and_track_ms"], "-"),
            ("  IK tracking alone", tracking, f["ik_tracking_per_point_us"]),
            ("  decision (the difference)", "-", f["decision_per_point_us"]),
            ("timing (Ruckig), human pace", f["part_timing_ms"], "-"),
            ("timing (Ruckig), --fastest (bell at the limits)", timing, "-"),
            ("JointPath + Trajectory messages", f["part_messages_ms"], "-"),
        ],
    )


def print_services(f: Figures, clients: list[int]) -> None:
    """Plans through every service beside in-process plans of the same run."""
    sys.stdout.write(
        "\nthe one-second reach through router + fit, decide, ik, timing and "
        f"planner on loopback ({f['services_plans']:.0f} plans per row, at "
        f"least {PER_CLIENT} per client):\n"
    )
    rows: list[tuple[str, float, float, float, object]] = [
        _service_row("in-process", "in_process", f)
    ]
    rows += [
        _service_row(f"services, {counted(k, 'client')}", f"services_{k}", f)
        for k in clients
    ]
    _table(
        ("plans", "p50 [ms]", "p99 [ms]", "plans/s", "p50 / in-process p50"),
        rows,
    )
    print_stage_hops(f)


def print_stage_hops(f: Figures) -> None:
    """Each stage's request here and through its service (medians [ms])."""
    stages = [k[len("stage_") : -len("_here_ms")] for k in f if k.endswith("_here_ms")]
    if not stages:
        return
    sys.stdout.write(
        "\neach stage's request of that reach, in this process and through its "
        "service (medians):\n"
    )
    fields = ("here", "service", "overhead", "handle", "inside", "trips")
    rows = [(name, *(f[f"stage_{name}_{k}_ms"] for k in fields)) for name in stages]
    _table(
        (
            "stage",
            "here [ms]",
            "service [ms]",
            "difference [ms]",
            "its work there [ms]",
            "+ its JSON [ms]",
            "trips [ms]",
        ),
        rows,
    )
    sys.stdout.write(
        "(its work there, + its JSON: as the service timed them; trips: service "
        "minus that, i.e. Zenoh there and back through the router, and this "
        "side's JSON)\n"
    )
    if "services_1_p50_ms" in f:
        through = sum(f[f"stage_{name}_service_ms"] for name in stages)
        sys.stdout.write(
            f"the three stages through their services add up to {through:.1f} ms; "
            f"a whole plan through the services took {f['services_1_p50_ms']:.1f} "
            "ms (1 client, p50), the planner's own work and the client's hop "
            "included (timed one after the other: the machine's speed may have "
            "changed in between)\n"
        )


def _service_row(
    label: str, key: str, f: Figures
) -> tuple[str, float, float, float, object]:
    ratio = f.get(f"{key}_ratio", "-")
    return (label, f[f"{key}_p50_ms"], f[f"{key}_p99_ms"], f[f"{key}_per_s"], ratio)


def print_bars(f: Figures, clients: list[int]) -> None:
    """Whether this run met the issues' bars (on this machine, at this load).

    The in-process bar is shown as measured twice: in rounds with the peers
    and the plan's parts (each plan runs after other code, with cold caches),
    and back to back beside the services (one plan after another, as a
    planning server runs them). The services' bar is for one client at a
    time: with more, each plan also waits for the others' (their p50 is shown
    above).
    """
    sys.stdout.write("\nbars:\n")
    rows = [_bar("one-second reach in-process, in rounds with peers, median",
                 f["plan_mp_ms"], IN_PROCESS_BAR_MS)]  # fmt: skip
    if "in_process_p50_ms" in f:
        rows.append(
            _bar("one-second reach in-process, back to back, median",
                 f["in_process_p50_ms"], IN_PROCESS_BAR_MS)
        )  # fmt: skip
    if 1 in clients:
        rows.append(
            _bar("through the services, 1 client, p50", f["services_1_p50_ms"],
                 SERVICES_BAR_MS)
        )  # fmt: skip
    _table(("bar", "measured [ms]", "bar [ms]", "met"), rows)


def _table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> None:
    """:func:`print_table`, a figure that is not a number (none measured) as ``-``."""
    print_table(headers, [[_figure(value) for value in row] for row in rows])


def _figure(value: Any) -> Any:
    """``value``, or ``"-"`` if it is a float NaN."""
    return "-" if isinstance(value, float) and math.isnan(value) else value


def _bar(label: str, measured: float, bar: float) -> tuple[str, float, float, str]:
    return (label, measured, bar, "yes" if measured < bar else "no")


def _versus(
    label: str, ours: float, figures: Figures, peer: str, part: str
) -> tuple[str, float, float, float]:
    """A row: ours [ms], the peer's [ms], and peer / ours."""
    return (label, ours, figures[f"{peer}_ms"], figures[f"{peer}_over_{part}"])
