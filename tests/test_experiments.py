"""armplan experiment similarity / handover: JSON contract, plots, the mathematics."""

from __future__ import annotations

import dataclasses
import json
import math
import re
import shlex
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from armplan.cli.main import main
from armplan.demo.task import DEFAULT_TASK, load_task
from armplan.experiments.handover import Starts, run_handover
from armplan.experiments.human_reference import human_reference
from armplan.experiments.normalised_time import at_tau
from armplan.experiments.posture_similarity import (
    least_similarity,
    posture_distance,
    posture_similarity,
)
from armplan.experiments.similarity import METHODS, mean_distance
from armplan.experiments.subject_reach import subject_reaches
from shared.demos import synthesize
from shared.demos.posture_from_points import (
    joints_from_points,
)
from shared.errors import InvalidInputError
from shared.messages.measure_params import MeasureParams
from shared.output_paths import check_output_folder
from shared.robot import Side, load_arm

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
SMALL = ["--subjects", "2", "--trials", "1", "--points", "1", "16", "--samples", "21"]
DOCS = Path(__file__).resolve().parents[1] / "docs" / "results.md"
#: The commands docs/results.md shows, exactly; the tests run each of them on
#: a small configuration (size options and --json added, --out redirected).
SIMILARITY_COMMANDS = [
    "armplan experiment similarity --out docs/results",
    "armplan experiment similarity --path planned --out docs/results",
    "armplan experiment similarity --palm --out docs/results",
]
HANDOVER_COMMANDS = [
    "armplan experiment handover --out docs/results",
    "armplan experiment handover --starts reference --out docs/results",
    "armplan experiment handover --mu 0.03 --omega 0.01 --out docs/results",
]
#: Not the paper's: random reaches and chains (tests/test_experiment_pace.py).
PACE_COMMANDS = ["armplan experiment pace --out docs/results"]


def documented(command: str, out: Path, *small: str) -> list[str]:
    """A documented command's arguments, writing to ``out``, with ``small`` added."""
    args = shlex.split(command)[1:]
    args[args.index("--out") + 1] = str(out)
    return [*args, *small, "--json"]


def option(args: list[str], name: str, default: str) -> str:
    """The value of ``name`` in ``args``, or ``default``."""
    return args[args.index(name) + 1] if name in args else default


def similarity_name(args: list[str]) -> str:
    """The file name (no suffix) a similarity command writes: its path source,
    and whether the palm turns."""
    palm = "-palm" if "--palm" in args else ""
    return f"similarity-{option(args, '--path', 'human')}{palm}"


def handover_name(args: list[str]) -> str:
    """The file name (no suffix) a handover command writes: its starts, and
    the measures' weights it was given."""
    starts = option(args, "--starts", "chained")
    weights = "".join(
        f"-{name}-{float(args[args.index('--' + name) + 1]):g}"
        for name in ("mu", "omega")
        if "--" + name in args
    )
    return f"handover-{starts}{weights}"


def run_json(args: list[str], capsys: pytest.CaptureFixture[str]) -> dict[str, Any]:
    code = main(args)
    out = capsys.readouterr().out
    assert code == 0, out
    return json.loads(out)


def assert_invalid_input(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """``armplan <args> --json`` exits 1 with ``message`` on stderr and a typed
    ``invalid_input`` error as its JSON."""
    code = main([*args, "--json"])
    captured = capsys.readouterr()
    assert code == 1
    assert message in captured.err
    assert json.loads(captured.out)["error"]["kind"] == "invalid_input"


def assert_png(path: Path) -> None:
    """A PNG file: its magic bytes, and matplotlib reads it back as an image."""
    from matplotlib.image import imread

    assert path.read_bytes()[:8] == PNG_MAGIC
    image = imread(path)
    assert image.ndim == 3 and image.shape[0] > 100 and image.shape[1] > 100


def test_the_docs_show_exactly_the_tested_commands() -> None:
    """Every ``armplan experiment`` command in docs/results.md is one tested here."""
    lines = [line.strip() for line in DOCS.read_text().splitlines()]
    shown = [line for line in lines if line.startswith("armplan experiment")]
    assert shown == SIMILARITY_COMMANDS + HANDOVER_COMMANDS + PACE_COMMANDS


def test_every_figure_in_the_docs_is_written_by_a_documented_command() -> None:
    """Each PNG docs/results.md embeds is a file name one of its commands writes."""
    text = DOCS.read_text()
    embedded = set(re.findall(r"\(results/([\w.-]+\.png)\)", text))
    written = set()
    for command in SIMILARITY_COMMANDS:
        name = similarity_name(shlex.split(command))
        written |= {f"{name}-{k}.png" for k in ("distribution", "point-means")}
    for command in HANDOVER_COMMANDS:
        written.add(f"{handover_name(shlex.split(command))}-similarity.png")
    written.add("pace-ratios.png")  # armplan experiment pace
    assert embedded == written
    assert all((DOCS.parent / "results" / name).is_file() for name in embedded)


def test_the_docs_show_the_tables_the_commands_wrote() -> None:
    """Each table file in docs/results/ appears in docs/results.md, verbatim."""
    text = DOCS.read_text()
    tables = sorted((DOCS.parent / "results").glob("*.md"))
    assert [t.stem for t in tables] == [
        "handover-chained-mu-0.03-omega-0.01", "handover-chained", "handover-reference",
        "pace", "similarity-human-palm", "similarity-human", "similarity-planned",
    ]  # fmt: skip
    for table in tables:
        assert table.read_text() in text, table.name


def documented_keys(name: str) -> set[str]:
    """The names in backquotes in the row of docs/results.md's file table
    for ``results/<name>...json``."""
    rows = [
        line
        for line in DOCS.read_text().splitlines()
        if line.startswith(f"| `results/{name}") and ".json`" in line.split("|")[1]
    ]
    assert len(rows) == 1, rows
    return set(re.findall(r"`([a-z_]+)`", rows[0]))


def json_keys(data: dict[str, Any]) -> set[str]:
    """The keys of an experiment's JSON, its own and each method's (and, for
    pace, of each method's reaches and chains); not the method names."""
    methods = {str(m) for m in METHODS}
    keys = set(data) - methods
    for method in methods & set(data):
        keys |= set(data[method])
        for part in data[method].values():
            if isinstance(part, dict) and not part.keys() & {"P1", "P16"}:
                keys |= set(part)
    return keys


@pytest.mark.parametrize(
    ("experiment", "name"),
    [(["similarity", "--palm", "--subjects", "1", "--trials", "1", "--points", "1",
       "--samples", "21"], "similarity"),
     (["handover", "--movements", "1"], "handover"),
     (["pace", "--reaches", "1", "--chains", "1", "--methods", "mp"], "pace")],
    ids=["similarity", "handover", "pace"],
)  # fmt: skip
def test_the_json_keys_are_the_documented_ones(
    experiment: list[str],
    name: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Every key of the JSON file (and each method's) is named in
    docs/results.md's file table, and --json prints that file with the
    paths written added (``files``). The table named neither the
    similarity's ``reaches`` nor where its counts by primitives are
    (``by_mp_primitive_count``, ``by_human_primitive_count``), nor the
    handover's ``samples``, nor pace's ``slow_short``, ``ratios``, ``errors``."""
    printed = run_json(
        ["experiment", *experiment, "--out", str(tmp_path), "--json"], capsys
    )
    files = printed.pop("files")
    written = json.loads(Path(files[0]).read_text())
    assert written == printed
    assert json_keys(written) - documented_keys(name) == set()
    assert "`--json` prints the JSON instead, with `files`" in " ".join(
        DOCS.read_text().split()
    )


@pytest.mark.parametrize("command", SIMILARITY_COMMANDS)
def test_similarity_command_json_tables_and_plots(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A documented similarity run, small: each method's errors, a table, two PNGs."""
    args = documented(command, tmp_path, *SMALL)
    name, palm = similarity_name(args), "--palm" in args
    data = run_json(args, capsys)
    for method in ("mp", "least-norm", "single"):
        numbers = data[method]
        assert numbers["reaches"] == 4
        assert set(numbers["per_point_mean_elbow_error_m"]) == {"P1", "P16"}
        assert 0.0 < numbers["mean_elbow_error_m"] < 0.05
        per_point = list(numbers["per_point_mean_elbow_error_m"].values())
        assert numbers["mean_elbow_error_m"] == pytest.approx(np.mean(per_point))
        s = numbers.get("mean_posture_similarity")
        assert (s is not None) == palm
        assert s is None or least_similarity(5) < s < 1.0
    assert data["protocol"]["path"] == option(args, "--path", "human")
    assert data["protocol"]["palm"] == palm and data["protocol"]["skipped"] == []
    bars = {"below_1cm", "below_least-norm", "below_single"}
    if palm:
        bars |= {"posture_above_least-norm", "posture_above_single"}
    assert set(data["bars"]) == bars
    assert_png(tmp_path / f"{name}-distribution.png")
    assert_png(tmp_path / f"{name}-point-means.png")
    table = (tmp_path / f"{name}.md").read_text()
    assert "| P16 |" in table
    assert ("mean S" in table) == palm
    assert json.loads((tmp_path / f"{name}.json").read_text())["mp"]


def test_similarity_with_a_demo_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--demos reads an MCAP file: its one subject and point are the experiment."""
    from shared.demos import write_demos

    demos = synthesize(3, subjects=1, trials=2, points=(6,))
    write_demos(tmp_path / "demos.mcap", demos)
    data = run_json(
        ["experiment", "similarity", "--demos", str(tmp_path / "demos.mcap"),
         "--samples", "11", "--out", str(tmp_path), "--json"],
        capsys,
    )  # fmt: skip
    assert list(data["mp"]["per_point_mean_elbow_error_m"]) == ["P6"]
    assert data["mp"]["reaches"] == 1


def test_with_the_palm_nao_starts_in_the_subjects_posture_and_ends_on_its_palm() -> (
    None
):
    """--palm: the subject's postures on NAO put NAO's arm on the subject's
    points; every method starts there and ends with the palm turned as far
    towards the subject's last as the forearm allows (no roll left)."""
    from armplan.experiments.nao_reach import PathSource, nao_reach
    from armplan.experiments.similarity import palm_turn, subject_postures
    from services.planner.stages import LocalStages
    from shared.geometry.palm import roll_error

    arm = load_arm("right")
    tau = np.linspace(0.0, 1.0, 21)
    reach = subject_reaches(synthesize(4, subjects=1, trials=2, points=(6,)), tau)[0]
    subject = subject_postures(arm, reach)
    points = [arm.fk(q) for q in subject]
    assert mean_distance(np.array([p.elbow for p in points]), reach.elbow) < 1e-3
    assert mean_distance(np.array([p.wrist for p in points]), reach.wrist) < 1e-3
    turn = palm_turn(arm, subject)
    for method in METHODS:
        nao = nao_reach(arm, LocalStages(), reach, method, PathSource.HUMAN, tau,
                        turn=turn)  # fmt: skip
        assert np.allclose(nao.q[0], subject[0])
        rotation = arm.kinematics(nao.q[-1]).wrist_rotation
        assert abs(roll_error(rotation, 1.0, turn.palm)) < 1e-3, method


def test_palm_without_wrist_frames_is_a_clear_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Demonstrations with no wrist frames (marker sets without a hand) cannot
    say where the palm faced: --palm names the subject and point."""
    from shared.demos import write_demos

    demos = synthesize(3, subjects=1, trials=1, points=(6,))
    bare = demos._replace(trials=[t._replace(wrist_frame=None) for t in demos.trials])
    write_demos(tmp_path / "demos.mcap", bare)
    demo_file = str(tmp_path / "demos.mcap")
    code = main(["experiment", "similarity", "--demos", demo_file, "--palm",
                 "--samples", "11", "--out", str(tmp_path), "--json"])  # fmt: skip
    captured = capsys.readouterr()
    assert code == 1
    assert "trials at P6 have no wrist frames" in captured.err


def test_with_the_palm_mp_is_the_nearest_to_the_subjects_postures(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """On demonstrations of the set the motion model was fitted on (seed 0),
    with the subject's palm, mp's postures are nearer the subjects' than both
    baselines' (with the locked joints at ``LOCKED`` = 0.1 where the palm
    turns, mp was below both, 0.969 against 0.977: the roll fell on
    ElbowYaw)."""
    size = ["--seed", "0", "--subjects", "2", "--trials", "1", "--samples", "21"]
    args = ["experiment", "similarity", "--palm", *size, "--out", str(tmp_path)]
    data = run_json([*args, "--json"], capsys)
    assert data["bars"]["posture_above_least-norm"]["met"]
    assert data["bars"]["posture_above_single"]["met"]


@pytest.mark.parametrize("command", HANDOVER_COMMANDS)
def test_handover_command_json_and_plot(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A documented handover run, 2 movements: mean S in (0, 1], a Fig. 18 PNG."""
    args = documented(command, tmp_path, "--movements", "2")
    starts = option(args, "--starts", "chained")
    data = run_json(args, capsys)
    floor = least_similarity(5)
    for method in ("mp", "least-norm", "single"):
        numbers = data[method]
        assert floor <= numbers["min_similarity"] <= numbers["mean_similarity"] <= 1.0
        assert len(numbers["per_movement_mean_similarity"]) == 2
    assert data["mp"]["primitives"][0]  # the method names what moved the arm
    assert data["protocol"]["starts"] == starts
    omega = float(option(args, "--omega", str(MeasureParams().omega)))
    assert data["protocol"]["measures"]["omega"] == omega
    assert set(data["bars"]) == {"above_least-norm", "above_single"}
    name = handover_name(args)
    assert_png(tmp_path / f"{name}-similarity.png")
    assert "take the red block" in (tmp_path / f"{name}.md").read_text()
    assert json.loads((tmp_path / f"{name}.json").read_text())["mp"]


@pytest.mark.parametrize(
    ("count", "message"),
    [("0", "--movements must be at least 1, got 0"),
     ("13", "--movements 13: the task has 12 movements")],
)  # fmt: skip
def test_movements_out_of_the_task_is_a_clear_error(
    count: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """--movements outside 1..(the task's movements): exit 1, the bound named."""
    assert_invalid_input(
        ["experiment", "handover", "--movements", count], message, capsys
    )


def test_movements_takes_the_first_movements_of_the_task() -> None:
    """The first N movements of the task, in order, every target of a phase one."""
    arm = load_arm("right")
    task = load_task(DEFAULT_TASK)
    names = [m.name for m in human_reference(arm, task)]
    assert len(names) == len(task.targets()) == 12
    assert names[5:8] == ["set the blue block down", "wave goodbye 1", "wave goodbye 2"]
    assert [m.name for m in human_reference(arm, task, 7)] == names[:7]


def test_from_the_persons_posture_every_method_starts_at_s_one() -> None:
    """starts=reference: NAO starts each movement in the person's posture (S = 1).

    A tracked path's first posture is its start posture, with every method,
    also when the palm is still to turn.
    """
    task = load_task(DEFAULT_TASK)
    _, series = run_handover(task, movements=3, starts=Starts.REFERENCE)
    for one in series:
        first = [one.similarity[one.movement == k][0] for k in range(3)]
        assert np.allclose(first, 1.0), one.method.value


def test_similarity_of_identical_postures_is_one(rng: np.random.Generator) -> None:
    """S(q, q) = 1 (dist 0) for any posture within the ranges."""
    limits = load_arm("right").limits
    q = rng.uniform(limits.lower, limits.upper, size=(20, 5))
    assert np.allclose(posture_similarity(q, q, limits), 1.0)


def test_similarity_of_opposite_extremes_is_the_minimum(
    rng: np.random.Generator,
) -> None:
    """Every joint at opposite ends: dist = sqrt(5), S = 1/(1+sqrt(5)), the least."""
    limits = load_arm("right").limits
    s = posture_similarity(limits.lower, limits.upper, limits)
    assert s == pytest.approx(1.0 / (1.0 + math.sqrt(5.0)))
    assert s == pytest.approx(least_similarity(5))
    a = rng.uniform(limits.lower, limits.upper, size=(500, 5))
    b = rng.uniform(limits.lower, limits.upper, size=(500, 5))
    assert np.all(posture_similarity(a, b, limits) > s)


def test_distance_is_normalised_by_each_joints_range() -> None:
    """One joint moved by its whole range: dist 1, whatever the joint."""
    limits = load_arm("left").limits
    for joint in range(5):
        a, b = limits.lower.copy(), limits.lower.copy()
        b[joint] = limits.upper[joint]
        assert posture_distance(a, b, limits) == pytest.approx(1.0)


def test_similarity_rejects_mismatched_postures() -> None:
    """Postures of the wrong shape are a typed error naming the shapes."""
    limits = load_arm("right").limits
    with pytest.raises(InvalidInputError, match=r"\(4,\) and \(4,\) do not match 5"):
        posture_similarity(np.zeros(4), np.zeros(4), limits)


def test_elbow_error_of_the_human_against_itself_is_zero() -> None:
    """A subject's single trial, read at its own tau, is its reach: error 0."""
    demos = synthesize(5, subjects=1, trials=1, points=(3,))
    trial = demos.trials[0]
    own = (trial.times - trial.times[0]) / (trial.times[-1] - trial.times[0])
    reach = subject_reaches(demos, own)[0]
    assert mean_distance(reach.elbow, trial.elbow) < 1e-12
    assert mean_distance(reach.wrist, trial.wrist) < 1e-12
    assert mean_distance(reach.elbow + np.array([0.0, 0.0, 0.01]), trial.elbow) == (
        pytest.approx(0.01)
    )


def test_normalised_time_aligns_start_and_end() -> None:
    """Two movements of different durations meet at tau = 0 and tau = 1."""
    slow = at_tau(
        np.linspace(0, 2.0, 9), np.linspace(0, 1, 9)[:, None], np.array([0, 0.5, 1])
    )
    fast = at_tau(
        np.linspace(3, 3.5, 5), np.linspace(0, 1, 5)[:, None], np.array([0, 0.5, 1])
    )
    assert np.allclose(slow, fast) and np.allclose(slow[:, 0], [0, 0.5, 1])


def test_human_points_become_the_nao_posture_that_made_them(
    rng: np.random.Generator,
) -> None:
    """Points made by FK of a posture give back that posture's elbow and wrist."""
    arm = load_arm("right")
    for _ in range(10):
        q = rng.uniform(arm.limits.lower + 0.2, arm.limits.upper - 0.2)
        points = arm.fk(q)
        palm = arm.rotation(q, "wrist")[:, 1]
        found = joints_from_points(arm, points.elbow, points.wrist, palm, q + 0.05)
        again = arm.fk(found)
        assert np.linalg.norm(again.elbow - points.elbow) < 1e-6
        assert np.linalg.norm(again.wrist - points.wrist) < 1e-6
        assert found[4] == pytest.approx(q[4], abs=1e-6)  # the palm fixes WristYaw


def test_bad_grid_point_is_a_clear_error(capsys: pytest.CaptureFixture[str]) -> None:
    """--points 17: exit code 1 and a message naming the point."""
    code = main(["experiment", "similarity", "--points", "17", "--json"])
    captured = capsys.readouterr()
    assert code == 1
    assert "grid point 17 does not exist" in captured.err
    assert json.loads(captured.out)["error"]["kind"] == "invalid_input"


def test_a_left_arm_task_is_a_clear_error() -> None:
    """The human reach model moves a right arm: a left-arm task says so."""
    task = dataclasses.replace(load_task(DEFAULT_TASK), arm=Side.LEFT)
    with pytest.raises(InvalidInputError, match=r"moves a right arm; .* left arm"):
        human_reference(load_arm("left"), task)


def test_a_task_with_palms_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """NAO's palm is the person's: a task's palm was silently not used; now the
    experiment refuses it, naming the target, before anything is written."""
    task = tmp_path / "palm-task.json"
    wave = [{"position": [0.06, -0.16, 0.22]}, {"position": [0.06, -0.11, 0.23]}]
    wave[1]["palm"] = [0.0, 0.0, -1.0]
    phases = [{"name": "take", "targets": [{"position": [0.14, -0.10, 0.06]}]}]
    phases.append({"name": "wave", "targets": wave})
    task.write_text(json.dumps({"arm": "right", "phases": phases}))
    out = tmp_path / "out"
    argv = ["experiment", "handover", "--task", str(task), "--out", str(out)]
    assert main([*argv, "--json"]) == 1
    error = json.loads(capsys.readouterr().out)["error"]
    assert error["kind"] == "invalid_input"
    assert error["message"] == (
        "the task's target 'wave 2' gives a palm direction; the handover "
        "experiment takes NAO's palm from the human reference (the person's "
        "palm at each movement's end), so leave the task's palms out"
    )
    assert error["evidence"]["target"] == "wave 2"
    assert not list(out.glob("*"))


def test_reference_starts_in_the_tasks_start_and_ends_on_its_targets() -> None:
    """The person starts in NAO's start posture; NAO's targets are the person's.

    Where the person's posture lies outside NAO's ranges (ElbowYaw at its
    limit when the red block is set down) the reference's wrist misses the
    target by under a millimetre.
    """
    arm = load_arm("right")
    task = load_task(DEFAULT_TASK)
    reference = human_reference(arm, task, movements=3)
    assert [m.name for m in reference] == [p.name for p in task.phases[:3]]
    assert np.allclose(reference[0].q[0], task.start, atol=1e-6)
    for move in reference:
        end = arm.fk(move.q[-1]).wrist
        assert np.linalg.norm(end - np.array(move.target.position)) < 1e-3
        assert move.target.palm is not None


def test_methods_are_the_method_and_both_baselines() -> None:
    """The experiments compare mp with least-norm and single, mp first."""
    assert [m.value for m in METHODS] == ["mp", "least-norm", "single"]


@pytest.mark.parametrize(
    ("option", "message"),
    [(["--samples", "1000000000"], "need 11 to 10001 samples of normalised time"),
     (["--samples", "2"], "need 11 to 10001 samples of normalised time, got 2"),
     (["--seed", "-1"], "seed must be 0 or more, got -1"),
     (["--subjects", "5000"], "subjects must be 1..1000, got 5000"),
     (["--trials", "0"], "trials must be 1..1000, got 0"),
     (["--points", "17"], "grid point 17 does not exist")],
)  # fmt: skip
def test_similarity_options_out_of_range_are_clear_errors(
    option: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """Sizes that would exhaust memory (a billion samples once did) or that numpy
    would refuse with a traceback (a negative seed): exit 1, the bound named."""
    assert_invalid_input(["experiment", "similarity", *option], message, capsys)


@pytest.mark.parametrize(
    ("option", "message"),
    [(["--samples", "2"], "need 11 to 10001 samples of normalised time, got 2"),
     (["--mu", "-1"], "mu"),
     (["--model", "absent-model.json"], "absent-model.json")],
)  # fmt: skip
def test_options_are_refused_before_the_demonstrations_are_read(
    option: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A bad option with demonstrations that do not exist: the option is
    named, not the file (they were checked only after the demonstrations
    were read or made: 9 s of synthesis for a typo)."""
    missing = str(tmp_path / "absent.mcap")
    out = tmp_path / "results"
    code = main(
        ["experiment", "similarity", "--demos", missing, *option, "--out", str(out)]
    )
    error = capsys.readouterr().err
    assert code == 1
    assert message in error and "absent.mcap" not in error
    assert not out.exists()


def test_synthetic_options_with_demonstration_files_are_clear_errors(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--subjects (or --trials, --seed, --points) shape the synthetic set; with
    --demos it was silently ignored. Refused, naming it, before the file is
    even read."""
    missing = str(tmp_path / "absent.mcap")
    assert_invalid_input(
        ["experiment", "similarity", "--demos", missing, "--subjects", "5"],
        "--subjects is an option of the synthetic demonstrations",
        capsys,
    )


#: Each experiment at its smallest, for the checks made before any work.
SMALLEST = pytest.mark.parametrize(
    "experiment",
    [["similarity", "--subjects", "1", "--trials", "1", "--points", "1"],
     ["handover", "--movements", "1"],
     ["pace", "--reaches", "1", "--chains", "0"]],
    ids=["similarity", "handover", "pace"],
)  # fmt: skip


@SMALLEST
def test_an_output_folder_that_is_a_file_is_refused_before_the_work(
    experiment: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out naming a file: exit 1 with the path named and the file untouched,
    checked up front (the similarity experiment used to run to its end first,
    then fail to make the folder)."""
    out = tmp_path / "results.txt"
    out.write_text("keep me")
    assert_invalid_input(
        ["experiment", *experiment, "--out", str(out)],
        f"cannot write into {out} (--out): it is a file, not a folder",
        capsys,
    )
    assert out.read_text() == "keep me"


@SMALLEST
def test_an_output_folder_that_cannot_be_made_is_refused_before_the_work(
    experiment: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out under /proc, which the check up front cannot foresee (as root,
    /proc looks writable): the folder is made before any work, so the error
    names --out and the OS's reason, and comes before the motion model is
    read (a missing --model file here). It used to come after every reach
    was planned, as "cannot make the output directory ...: [Errno 2] ..."."""
    out = f"/proc/armplan-test-{tmp_path.name}/results"
    try:
        check_output_folder(out)
    except InvalidInputError:
        pytest.skip("/proc is not writable to this user: refused up front anyway")
    assert_invalid_input(
        ["experiment", *experiment, "--out", out,
         "--model", str(tmp_path / "missing.json")],
        f"cannot write into {out} (--out): No such file or directory",
        capsys,
    )  # fmt: skip


def test_a_run_that_fails_after_the_check_leaves_no_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out new/results with a motion model that is missing: the error
    names the model, and neither folder is left behind (the check up
    front makes them to see that it can, and removes them again)."""
    out = tmp_path / "new" / "results"
    code = main(["experiment", "handover", "--movements", "1", "--out", str(out),
                 "--model", str(tmp_path / "missing.json")])  # fmt: skip
    assert code == 1
    assert "no such motion-model file" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("experiment", "files"),
    [(["similarity", "--subjects", "1", "--trials", "1", "--points", "1"],
      ["similarity-human.json", "similarity-human.md",
       "similarity-human-distribution.png", "similarity-human-point-means.png"]),
     (["handover", "--movements", "1"],
      ["handover-chained.json", "handover-chained.md",
       "handover-chained-similarity.png"]),
     (["pace", "--reaches", "1", "--chains", "0"],
      ["pace.json", "pace.md", "pace-ratios.png"])],
    ids=["similarity", "handover", "pace"],
)  # fmt: skip
def test_a_failed_last_file_leaves_the_older_results_whole(
    experiment: list[str],
    files: list[str],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A folder where the last figure goes: exit 1 naming it; the older JSON,
    tables and figures stay as they were (the new JSON and tables used to
    replace them, leaving a mix) and no partial file is left."""
    *older, last = (tmp_path / name for name in files)
    for path in older:
        path.write_text(f"older {path.name}")
    last.mkdir()
    assert_invalid_input(
        ["experiment", *experiment, "--out", str(tmp_path)],
        f"cannot write {last}: Is a directory",
        capsys,
    )
    assert [path.read_text() for path in older] == [
        f"older {path.name}" for path in older
    ]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(files)


@pytest.mark.parametrize(
    ("experiment", "arm"),
    [(["similarity", "--subjects", "1", "--trials", "1", "--points", "1"], "right"),
     (["handover", "--movements", "1"], "right"),
     (["pace", "--reaches", "1", "--chains", "0", "--arm", "left"], "left")],
    ids=["similarity", "handover", "pace"],
)  # fmt: skip
def test_the_protocol_names_the_model_and_the_arm(
    experiment: list[str],
    arm: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Runs with another motion model or arm are told apart by their JSON: the
    protocol names the model file given (or "shipped") and the arm."""
    from services.fit import default_model, save_model

    path = tmp_path / "model.json"
    save_model(default_model(), path)
    base = ["experiment", *experiment, "--out", str(tmp_path / "out"), "--json"]
    for model, named in (([], "shipped"), (["--model", str(path)], str(path))):
        protocol = run_json([*base, *model], capsys)["protocol"]
        assert (protocol["model"], protocol["arm"]) == (named, arm)


def test_the_models_fitted_weights_are_every_methods(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """With ``--model``, every method tracks with that model's fitted weights
    (the protocol names them), and ``--omega`` overrides only omega."""
    from services.fit import default_model, save_model
    from shared.messages.motion_model import FittedWeights

    weights = FittedWeights(mu=0.5, omega=0.2, samples=100, explained=0.9)
    path = tmp_path / "model.json"
    save_model(default_model().model_copy(update={"weights": weights}), path)
    base = ["experiment", "handover", "--movements", "1", "--model", str(path)]
    data = run_json([*base, "--out", str(tmp_path), "--json"], capsys)
    measures = data["protocol"]["measures"]
    assert (measures["mu"], measures["omega"]) == (0.5, 0.2)
    data = run_json([*base, "--omega", "0", "--out", str(tmp_path), "--json"], capsys)
    measures = data["protocol"]["measures"]
    assert (measures["mu"], measures["omega"]) == (0.5, 0.0)


def test_the_default_output_folder_is_documented() -> None:
    """docs/results.md says where the files go without --out (it did not)."""
    from armplan.cli.commands.experiment import OUT

    assert f"Without `--out` the files go into `./{OUT}/`" in DOCS.read_text()
