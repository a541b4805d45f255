"""``armplan bench --json`` on a tiny configuration: every part, every ratio, no
process left behind (figures are not timed against anything)."""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
from pathlib import Path

import pytest
from armplan_cli import armplan

from armplan.bench import ik_cost, service_latency
from armplan.bench.machine import cpu_model
from armplan.bench.report import print_bars, print_ik, print_planning
from armplan.bench.service_latency import PER_CLIENT, plans_for
from armplan.cli.commands.bench import _client_counts
from armplan.cli.main import main
from shared.bus.config import DEFAULT_QUEUE_LIMIT
from shared.bus.lifeline import PARENT_ENV
from shared.compiled import running_compiled
from shared.errors import ServiceUnavailableError

TINY = ["bench", "--targets", "1", "--repeats", "1", "--plans", "2"]
CLIENTS = (1, 3)
#: Each ratio of the JSON, as (ratio, numerator, denominator).
QUOTIENTS = [
    ("speedup_vs_slsqp", "slsqp_per_target_ms", "ik_per_target_ms"),
    ("speedup_vs_ikpy", "ikpy_per_target_ms", "ik_per_target_ms"),
    ("toppra_over_plan", "toppra_ms", "plan_mp_ms"),
    ("ikpy_over_plan", "ikpy_ms", "plan_mp_ms"),
    ("toppra_over_timing", "toppra_ms", "part_timing_fastest_ms"),
    ("ikpy_over_tracking", "ikpy_ms", "part_tracking_ms"),
] + [
    (f"services_{k}_ratio", f"services_{k}_p50_ms", "in_process_p50_ms")
    for k in CLIENTS
]
#: Figures that are times [ms, us] or rates [1/s]: positive.
POSITIVE = (
    {name for triple in QUOTIENTS for name in triple}
    | {
        "gpm_step_per_point_us",
        "ik_per_target_p99_ms",
        "plan_least_norm_ms",
        "plan_single_ms",
        "in_process_p99_ms",
        "in_process_per_s",
        "ik_tracking_per_point_us",
    }
    | {f"services_{k}_{what}" for k in CLIENTS for what in ("p99_ms", "per_s")}
)


def _orphans(parent: int) -> list[int]:
    """Live processes started with ``ARMPLAN_PARENT_PID=parent`` (the launcher's)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            environ = (entry / "environ").read_bytes().split(b"\0")
            state = (entry / "stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:  # gone meanwhile, or not ours
            continue
        if f"{PARENT_ENV}={parent}".encode() in environ and state != "Z":
            found.append(int(entry.name))
    return found


@pytest.fixture(scope="module")
def figures() -> dict[str, float]:
    """The JSON of one tiny run, through the services with 1 and 3 clients."""
    out = io.StringIO()  # module scope: capsys is per test
    with contextlib.redirect_stdout(out):
        code = main([*TINY, "--clients", ",".join(map(str, CLIENTS)), "--json"])
    assert code == 0
    parsed: dict[str, float] = json.loads(out.getvalue())
    return parsed


def test_every_ratio_is_the_quotient_of_the_figures_it_compares(
    figures: dict[str, float],
) -> None:
    """Ratio = peer (or services) over ours (or in-process), from the same JSON."""
    for ratio, top, bottom in QUOTIENTS:
        assert figures[ratio] == pytest.approx(figures[top] / figures[bottom]), ratio


def test_times_and_rates_are_positive_and_finite(figures: dict[str, float]) -> None:
    """Every time and rate is a positive finite number; fractions lie in [0, 1]."""
    for name in POSITIVE:
        assert math.isfinite(figures[name]) and figures[name] > 0.0, name
    assert figures["decision_per_point_us"] >= 0.0
    for name in [k for k in figures if k.endswith("reached_fraction")]:
        assert 0.0 <= figures[name] <= 1.0, name


def test_the_work_and_the_machine_are_recorded(figures: dict[str, float]) -> None:
    """The one-second reach of about 100 points in both planning parts; the
    plans counted; the processor, CPUs and the load average over the run."""
    assert figures["cpu_model"] == cpu_model()
    assert figures["targets"] == 1.0 and figures["services_plans"] == 2.0
    # each client count keeps its clients busy: 10 plans per client at least
    assert figures["services_1_plans"] == 10.0 and figures["services_3_plans"] == 30.0
    assert figures["in_process_plans"] == 2.0
    assert figures["plan_points"] == figures["services_path_points"]
    assert 90 <= figures["plan_points"] <= 110
    assert figures["plan_duration_s"] == pytest.approx(1.0, abs=0.1)
    assert figures["cpus"] == os.cpu_count()
    for name in ("load_average_start", "load_average_end"):
        assert figures[name] >= 0.0
    assert figures["compiled"] == float(running_compiled())
    assert not [k for k in figures if k.startswith("services_8")]  # only 1 and 3


DOCS = Path(__file__).resolve().parents[1] / "docs" / "benchmarks.md"


def documented_names() -> list[str]:
    """docs/benchmarks.md's ``--json`` names as patterns: ``<a|b>`` one of
    them, ``<part>`` any word, and a name begun with ``_`` the one before it
    with another ending (``services_<clients>_p50_ms``, ``_p99_ms``)."""
    text = DOCS.read_text().split("`--json` prints the same figures", 1)[1]
    patterns: list[str] = []
    stem = ""
    for name in re.findall(r"`([a-z0-9_<>|]+)`", text):
        if name.startswith("_"):
            name = stem + name
        else:
            cut = name.rfind(">") + 1 or name.rfind("_")
            stem = name[:cut]
        name = re.sub(r"<([a-z|]+\|[a-z|]+)>", r"(\1)", name)
        patterns.append(re.sub(r"<[a-z]+>", "[a-z0-9_]+", name))
    return patterns


def test_every_figure_is_named_in_the_docs(figures: dict[str, float]) -> None:
    """Each key of ``--json`` is one docs/benchmarks.md names (``compiled``,
    ``targets``, the reached fractions: 22 of them were not)."""
    patterns = documented_names()
    unnamed = [k for k in figures if not any(re.fullmatch(p, k) for p in patterns)]
    assert unnamed == []


def test_each_stage_is_timed_here_and_through_its_service(
    figures: dict[str, float],
) -> None:
    """decide, ik and timing: both times positive, the difference their gap;
    the service's own account of its work fits inside its time through it."""
    for stage in ("decide", "ik", "timing"):
        here, there = (
            figures[f"stage_{stage}_here_ms"],
            figures[f"stage_{stage}_service_ms"],
        )
        assert here > 0.0 and there > 0.0, stage
        assert figures[f"stage_{stage}_overhead_ms"] == pytest.approx(there - here)
        handle, inside = (
            figures[f"stage_{stage}_handle_ms"],
            figures[f"stage_{stage}_inside_ms"],
        )
        assert 0.0 < handle < inside < there, stage
        assert figures[f"stage_{stage}_trips_ms"] == pytest.approx(there - inside)


def test_no_service_process_outlives_the_benchmark(figures: dict[str, float]) -> None:
    """The router and the services the benchmark started have all exited."""
    assert figures["services_1_per_s"] > 0.0  # they did run
    assert _orphans(os.getpid()) == []


def test_no_services_skips_them() -> None:
    """``python -m armplan bench --no-services``: no figure through the
    services; the IK and the planning figures still there, every ratio of
    theirs positive, the IK target reached."""
    out = armplan(*TINY, "--no-services", "--json")
    assert out.returncode == 0, out.stderr
    figures = json.loads(out.stdout)
    assert figures["ik_reached_fraction"] == 1.0
    assert not [
        k for k in figures if k.startswith(("services_", "in_process", "stage_"))
    ]
    for ratio, _, _ in QUOTIENTS:
        if not ratio.startswith("services_"):
            assert figures[ratio] > 0.0, ratio
    assert figures["plan_points"] > 90  # the one-second reach at 100 Hz


@pytest.mark.parametrize("clients", ["0", "1,x", ""])
def test_bad_client_counts_are_refused(
    clients: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """--clients must be integers 1..256, comma-separated: usage error."""
    with pytest.raises(SystemExit) as exit_:
        main(["bench", "--clients", clients])
    assert exit_.value.code == 2
    assert "not a comma-separated list of client counts, each 1..256" in (
        capsys.readouterr().err
    )


@pytest.mark.parametrize("clients", ["257", "8,300", "1000"])
def test_more_clients_than_the_planner_queues_are_refused_at_once(
    clients: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """More clients than the planner lets wait (DEFAULT_QUEUE_LIMIT) failed
    service_busy after the whole run (300: 27 s, exit 1): now a usage error
    before any work, naming --clients and the limit."""
    with pytest.raises(SystemExit) as exit_:
        main(["bench", "--clients", clients])
    assert exit_.value.code == 2
    err = " ".join(capsys.readouterr().err.split())
    assert "argument --clients:" in err
    assert "more than the planner's queue limit (256 requests waiting)" in err
    assert DEFAULT_QUEUE_LIMIT == 256 and _client_counts("1,256") == [1, 256]


@pytest.mark.parametrize(
    "clients,repeated", [("2,2", "2"), ("1,8,1,8", "1, 8"), ("8,3,8", "8")]
)
def test_a_client_count_given_twice_is_refused(
    clients: str, repeated: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """--clients 2,2 ran both loads and printed two identical rows (the
    figures are kept under one key, services_2_*): now a usage error."""
    with pytest.raises(SystemExit) as exit_:
        main(["bench", "--clients", clients])
    assert exit_.value.code == 2
    err = " ".join(capsys.readouterr().err.split())
    assert (
        f"argument --clients: {clients!r} gives {repeated} clients more than "
        "once: each count is one row, give each once"
    ) in err


def test_a_negative_seed_is_refused_before_any_work(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """--seed -1 ran into numpy's ValueError once the IK benchmark began:
    now exit 1 before any work, the option named."""
    assert main([*TINY, "--no-services", "--seed", "-1"]) == 1
    assert "--seed must be 0 or more, got -1" in capsys.readouterr().err


def test_too_many_targets_are_refused_before_any_work(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """--targets 100000000 drew and prepared every target before the first
    was timed, gigabytes and minutes without a sign: exit 1 at once, the
    option and its range named."""
    assert main(["bench", "--targets", "100000000", "--json"]) == 1
    captured = capsys.readouterr()
    assert "--targets must be 1..10000, got 100000000" in captured.err
    assert json.loads(captured.out)["error"]["evidence"]["field"] == "targets"


@pytest.mark.parametrize(
    ("option", "why"),
    [
        ("--repeats", "every round's calls are made before the first is timed"),
        ("--plans", "every plan's call is made before the first is timed"),
        (
            "--ikpy-passes",
            "every pass's call is made before the first is timed, and each takes "
            "seconds",
        ),
    ],
)
def test_too_many_repeats_or_plans_are_refused_before_any_work(
    option: str, why: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """--repeats 100000000 made a list of every round's calls before timing
    the first (gigabytes, no progress shown); --ikpy-passes too; --plans
    too, each plan's call (with --no-services, unused, it ran the whole
    bench): exit 1 at once, the option, its range and the reason named."""
    argv = ["bench", "--targets", "1", option, "1000000000", "--no-services"]
    assert main([*argv, "--json"]) == 1
    captured = capsys.readouterr()
    most = 100 if option == "--ikpy-passes" else 10000
    assert f"{option} must be 1..{most}, got 1000000000: {why}" in captured.err
    field = json.loads(captured.out)["error"]["evidence"]["field"]
    assert field == option[2:].replace("-", "_")


def test_zero_plans_are_refused(capsys: pytest.CaptureFixture[str]) -> None:
    """--plans 0: exit 1, the option named."""
    assert main(["bench", "--plans", "0"]) == 1
    assert "--plans must be at least 1" in capsys.readouterr().err


def test_the_help_says_how_many_plans_go_through_the_services(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """--plans is the in-process count; each row through the services plans at
    least PER_CLIENT per client (the help said --plans was per client)."""
    with pytest.raises(SystemExit):
        main(["bench", "--help"])
    words = " ".join(capsys.readouterr().out.split())
    assert (
        "--plans PLANS plans in-process, 1 to 10000 (default 100); through the "
        f"services, for each client count, PLANS but at least {PER_CLIENT} per client"
    ) in words
    assert plans_for(100, 50) == 50 * PER_CLIENT and plans_for(100, 8) == 100


def test_the_bars_show_the_in_process_plan_both_ways(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """In rounds with the peers and back to back, each against the 10 ms bar;
    without the services' run there is no back-to-back figure to show."""
    figures = {"plan_mp_ms": 12.0, "in_process_p50_ms": 9.0, "services_1_p50_ms": 30.0}
    print_bars(figures, [1])
    rows = [r.split() for r in capsys.readouterr().out.splitlines()]
    met = {" ".join(r[:-3]): r[-1] for r in rows if r and r[-1] in ("yes", "no")}
    assert met == {
        "one-second reach in-process, in rounds with peers, median": "no",
        "one-second reach in-process, back to back, median": "yes",
        "through the services, 1 client, p50": "no",
    }
    print_bars({"plan_mp_ms": 12.0}, [])
    assert "back to back" not in capsys.readouterr().out


def test_figures_with_nothing_measured_print_as_a_dash(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """With 5 targets (seed 7) SLSQP reaches none: the rows on the targets
    both reached printed nan cells (the JSON gives null); now "-"."""
    figures = ik_cost.run(5, 7, lambda: None).figures()
    assert figures["common_targets"] == 0.0
    assert math.isnan(figures["speedup_vs_slsqp_on_common"])
    print_ik(figures)
    out = capsys.readouterr().out
    assert "nan" not in out.lower()
    rows = {" ".join(r.split()[:-3]): r.split()[-3:] for r in out.splitlines()[2:]}
    assert rows["on the 0 both reached [ms]"] == ["-", "-", "-"]
    assert rows["TPE ours - SLSQP, both reached [J]"] == ["-", "-", "-"]


def test_one_target_is_one_target(capsys: pytest.CaptureFixture[str]) -> None:
    """``--targets 1`` printed "IK of 1 random reachable targets"."""
    print_ik(ik_cost.run(1, 7, lambda: None).figures())
    assert capsys.readouterr().out.startswith(
        "IK of 1 random reachable target, means:\n"
    )


def test_the_peers_are_compared_on_like_work(figures: dict[str, float]) -> None:
    """toppra beside our --fastest timing (the nearest part of ours, unlike
    work), with both trajectories' durations; ikpy's accuracy beside ours; the
    SLSQP ratio also on the targets both reached (null if none)."""
    assert 0.0 < figures["toppra_duration_s"] <= figures["timing_fastest_duration_s"]
    assert figures["timing_fastest_duration_s"] < figures["plan_duration_s"]
    assert 0.0 <= figures["tracking_max_error_mm"] < 0.1
    assert figures["ikpy_max_error_mm"] >= 0.0
    common = figures["common_targets"]
    assert common in (0.0, 1.0)
    ratio = figures["speedup_vs_slsqp_on_common"]
    if common:
        assert ratio == pytest.approx(
            figures["slsqp_per_common_target_ms"] / figures["ik_per_common_target_ms"]
        )
    else:
        assert ratio is None


class _Ones(dict[str, float]):
    """Figures where every name not set is 1.0 (the table's layout only)."""

    def __missing__(self, key: str) -> float:
        return 1.0


def test_the_timing_row_says_it_compares_unlike_work(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Our --fastest is a jerk-limited bell at the limits' pace, toppra's is
    time-optimal without a jerk limit: the row says they are unlike work and
    the next one gives both durations (the row read as a like-for-like
    "fastest vs fastest" before)."""
    print_planning(_Ones(timing_fastest_duration_s=0.94, toppra_duration_s=0.45))
    lines = capsys.readouterr().out.splitlines()
    row = next(k for k, line in enumerate(lines) if "vs toppra (unlike" in line)
    assert lines[row].startswith("Ruckig --fastest vs toppra (unlike work)")
    durations = lines[row + 1].split()
    assert "jerk-limited" in lines[row + 1] and "time-optimal" in lines[row + 1]
    assert durations[-3:] == ["0.94000", "0.45000", "-"]


def test_a_router_port_in_use_is_said_not_sent_to_a_missing_log(
    busy_port: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """bench keeps no log of the services it starts: a router that could not
    listen was reported "(see its log)", a log that does not exist. Now the
    error says what the router printed: its port in use."""
    endpoint = f"tcp/127.0.0.1:{busy_port}"
    monkeypatch.setattr(service_latency, "free_endpoint", lambda: endpoint)
    with pytest.raises(ServiceUnavailableError) as caught:
        service_latency.run(n=1, clients=(1,))
    message = caught.value.message
    assert "see its log" not in message
    assert message.startswith(
        "service 'router' is unavailable: its process exited with code 1 while "
        "starting; its output ended: router: Zenoh configuration "
        f"--listen/--connect (listen/endpoints): cannot listen on {endpoint} ("
    )
    assert "Address already in use" in message
    assert caught.value.evidence["output"] in message
