"""The synthetic demonstration set: the paper's protocol, made by the reach model."""

from __future__ import annotations

import itertools
import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from shared.demos import DemoSet, nao_arm_size, synthesize
from shared.demos.anthropometry import (
    FOREARM_RATIO,
    RATIO_SPREAD,
    UPPER_ARM_RATIO,
    draw_subjects,
)
from shared.demos.grid import SPACING, grid_targets
from shared.demos.labels import primitive_name
from shared.demos.reach_model import AVERAGE_STYLE, plan_reach, sample_reach
from shared.demos.retarget import ArmTrack, retarget
from shared.demos.synthetic import MOST_TRIALS, _check
from shared.errors import InvalidInputError
from shared.primitives import MOTION_PRIMITIVES


@pytest.fixture(scope="module")
def demos() -> DemoSet:
    return synthesize(7)


def _runs(labels: list[str]) -> list[str]:
    return [name for name, _ in itertools.groupby(labels)]


def test_protocol_16_subjects_16_points_5_trials_100_hz(demos: DemoSet) -> None:
    """16 subjects reach 16 points 5 times each, sampled at 100 Hz."""
    assert len(demos.subjects) == 16
    assert len(demos.trials) == 16 * 16 * 5
    for name in demos.subjects:
        points = [t.point for t in demos.trials if t.subject == name]
        assert sorted(set(points)) == list(range(1, 17))
        assert all(points.count(p) == 5 for p in range(1, 17))
    steps = np.concatenate([np.diff(t.times)[:-1] for t in demos.trials])
    np.testing.assert_allclose(steps, 0.01, atol=1e-12)


def test_same_seed_same_set_other_seed_other_set() -> None:
    """Every random draw comes from the one seeded generator."""
    a, b, c = (synthesize(s, subjects=2, trials=1) for s in (3, 3, 4))
    for x, y in zip(a.trials, b.trials, strict=True):
        np.testing.assert_array_equal(x.wrist, y.wrist)
        assert x.labels == y.labels
    assert not np.allclose(a.trials[0].wrist[-1], c.trials[0].wrist[-1])


def test_arm_sizes_follow_the_anthropometric_ratios() -> None:
    """Upper arm and forearm are 0.186 H and 0.146 H, up to individual spread."""
    for person in draw_subjects(200, np.random.default_rng(1)):
        assert 1.4 < person.stature < 2.1
        for length, ratio in (
            (person.upper_arm, UPPER_ARM_RATIO),
            (person.forearm, FOREARM_RATIO),
        ):
            assert abs(length / person.stature / ratio - 1.0) < 5 * RATIO_SPREAD


def test_grid_is_4_by_4_points_10_cm_apart_in_front_of_the_shoulder() -> None:
    """Neighbours in a row or a column are 10 cm apart; all lie in front."""
    points = grid_targets(0.55).reshape(4, 4, 3)
    rows = np.linalg.norm(np.diff(points, axis=1), axis=2)
    columns = np.linalg.norm(np.diff(points, axis=0), axis=2)
    np.testing.assert_allclose(rows, SPACING)
    np.testing.assert_allclose(columns, SPACING)
    assert np.all(points[..., 0] > 0.3)


def test_reaches_start_hanging_and_end_on_the_target(demos: DemoSet) -> None:
    """At t = 0 the arm hangs; at the end the wrist is on the trial's target."""
    size = nao_arm_size("right")
    for trial in demos.trials[::37]:
        upper = trial.elbow[0] - trial.shoulder[0]
        assert upper[2] / np.linalg.norm(upper) < -0.9  # within ~25 deg of down
        assert trial.wrist[0][2] < trial.elbow[0][2] < trial.shoulder[0][2]
        np.testing.assert_allclose(trial.wrist[-1], trial.target)
        np.testing.assert_allclose(
            np.linalg.norm(trial.elbow - trial.shoulder, axis=1), size.upper_arm
        )
        np.testing.assert_allclose(
            np.linalg.norm(trial.wrist - trial.elbow, axis=1), size.forearm
        )


def test_durations_are_like_the_papers_table_4(demos: DemoSet) -> None:
    """Mean movement times per point lie in the paper's 0.55-1.01 s, +-10%."""
    for point in range(1, 17):
        mean = np.mean([t.times[-1] for t in demos.trials if t.point == point])
        assert 0.5 < mean < 1.11


def test_retargeting_keeps_segment_directions() -> None:
    """NAO's upper arm and forearm point where the human's did."""
    person = draw_subjects(1, np.random.default_rng(2))[0]
    reach = sample_reach(
        plan_reach(person, AVERAGE_STYLE, grid_targets(person.arm_length)[5]),
        person,
        100.0,
    )
    human = ArmTrack(np.zeros_like(reach.elbow), reach.elbow, reach.wrist)
    nao = retarget(human, nao_arm_size("right"))

    def unit(v: np.ndarray) -> np.ndarray:
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    np.testing.assert_allclose(unit(nao.elbow - nao.shoulder), unit(human.elbow))
    np.testing.assert_allclose(
        unit(nao.wrist - nao.elbow), unit(reach.wrist - reach.elbow)
    )


def test_minimum_jerk_reach_starts_and_ends_at_rest() -> None:
    """Noise-free, the wrist's speed is bell-shaped: ~0 at both ends."""
    person = draw_subjects(1, np.random.default_rng(3))[0]
    for target in grid_targets(person.arm_length)[::5]:
        reach = sample_reach(plan_reach(person, AVERAGE_STYLE, target), person, 100.0)
        speed = np.linalg.norm(np.diff(reach.wrist, axis=0), axis=1)
        assert speed[0] < 0.02 * speed.max() and speed[-1] < 0.02 * speed.max()


def test_labels_are_motion_primitives_in_the_shoulder_first_order(
    demos: DemoSet,
) -> None:
    """S_R E_P W_P comes first at most trials; one to three primitives a reach."""
    names = {p.name for p in MOTION_PRIMITIVES}
    first = 0
    for trial in demos.trials:
        assert trial.labels is not None and set(trial.labels) <= names
        runs = _runs(trial.labels)
        assert 1 <= len(set(runs)) <= 3
        first += runs[0] == "S_R E_P W_P"
        assert "E_R W_P" not in runs or runs[-1] == "E_R W_P"  # the elbow ends
    assert first > 0.75 * len(demos.trials)


def test_label_of_moving_joints() -> None:
    """Shoulder alone, shoulder and elbow, elbow alone, with the forearm's roll."""
    assert primitive_name(True, False, False) == "S_R E_P W_P"
    assert primitive_name(True, True, False) == "S_R E_PR W_P"
    assert primitive_name(True, True, True) == "S_R E_PR W_PR"
    assert primitive_name(False, True, False) == "E_R W_P"
    assert primitive_name(False, True, True) == "E_R W_P"
    assert primitive_name(False, False, True) is None


@pytest.mark.parametrize(
    ("arguments", "field"),
    [({"seed": -1}, "seed"), ({"subjects": 0}, "subjects"),
     ({"trials": 1001}, "trials"), ({"rate": 0.0}, "rate"),
     ({"rate": 1e6}, "rate"), ({"points": (0,)}, "points"),
     ({"subjects": 1000, "trials": 1000}, "trials")],
)  # fmt: skip
def test_arguments_out_of_their_domain_are_refused(
    arguments: dict[str, object], field: str
) -> None:
    """Each argument is checked at the boundary, before anything is drawn."""
    with pytest.raises(InvalidInputError) as info:
        synthesize(**arguments)  # type: ignore[arg-type]
    assert info.value.field == field


def test_the_set_is_limited_in_all_naming_the_product(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """1000 subjects x 1000 trials x 16 points was allowed: 16 million trials,
    over 200 GB and hours. Refused before anything is drawn or written."""
    path = tmp_path / "huge.mcap"
    argv = ["demos", "synth", "-o", str(path), "--subjects", "1000"]
    assert main([*argv, "--trials", "1000"]) == 1
    assert capsys.readouterr().err == (
        "armplan: error: 1000 subjects x 1000 trials x 16 points = 16000000 "
        f"trials, more than the {MOST_TRIALS} one set may have (the paper's "
        "protocol has 1280): ask for fewer subjects, trials or points\n"
    )
    assert not path.exists()
    with pytest.raises(InvalidInputError) as info:
        synthesize(subjects=1000, trials=3, points=tuple(range(1, 8)))
    assert info.value.evidence == {"field": "trials", "total": 21_000, "most": 20_000}
    assert MOST_TRIALS == 20_000
    _check(0, 1000, 2, 100.0, tuple(range(1, 11)))  # 20 000: the limit passes
