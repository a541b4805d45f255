"""The paper's Table 4 on NAO: S_R E_P W_P first, one to three primitives a reach."""

from __future__ import annotations

import numpy as np
import pytest

from services.decide.grid_table import (
    GridRow,
    LeftOut,
    demo_rows,
    grid_rows,
    left_out,
    runs,
    sequence,
)
from services.fit import default_model
from shared.demos import DemoSet, synthesize
from shared.demos.nao_grid import nao_grid
from shared.robot import Side, load_arm


@pytest.fixture(scope="module")
def rows() -> list[GridRow]:
    return grid_rows(default_model(), "right")


def test_table_4_shape(rows: list[GridRow]) -> None:
    """At most points S_R E_P W_P comes first; every reach uses one to three."""
    print()
    for row in rows:
        print(f"P{row.point:<2} {row.duration:.2f} s  " + "  ->  ".join(row.sequence))
    assert [r.point for r in rows] == list(range(1, 17))
    assert sum(r.sequence[0] == "S_R E_P W_P" for r in rows) >= 12
    assert all(1 <= len(r.sequence) <= 3 for r in rows)
    assert all(r.error < 1e-5 for r in rows)  # the tracker converges onto the goal


def test_times_grow_with_the_distance_like_table_4(rows: list[GridRow]) -> None:
    """Reaches to the higher rows (farther from the hanging hand) take longer."""
    by_row = [np.mean([r.duration for r in rows[i : i + 4]]) for i in range(0, 16, 4)]
    assert by_row == sorted(by_row)
    assert by_row[0] > 0.5 and by_row[-1] < 1.1


def test_grid_points_are_within_nao_reach() -> None:
    """The retargeted grid lies in NAO's reachable shell, in front of the shoulder."""
    arm = load_arm("right")
    shoulder = arm.fk(np.zeros(5)).shoulder
    low, high = arm.reach
    for target in nao_grid("right"):
        distance = np.linalg.norm(target.wrist - shoulder)
        assert low < distance < high and target.wrist[0] > 0.05
        assert np.linalg.norm(target.palm) == pytest.approx(1.0)


def test_sequences_and_runs() -> None:
    """Runs count repeats; short runs are set apart from the sequence."""
    labels = ["a", "a", "a", "b", "a", "a", "a", "c", "c", "c"]
    assert runs(labels) == [("a", 3), ("b", 1), ("a", 3), ("c", 3)]
    assert sequence(labels, 3) == (["a", "c"], 1)
    assert sequence(labels) == (["a", "b", "a", "c"], 0)


def test_demonstrations_give_the_same_kind_of_table() -> None:
    """The generator's labels per point: S_R E_P W_P first, three primitives."""
    table = demo_rows(synthesize(2, subjects=2, trials=2), "right")
    assert [r.point for r in table] == list(range(1, 17))
    for row in table:
        assert row.sequence[0] == "S_R E_P W_P" and 1 <= len(row.sequence) <= 3
        assert row.trials == 4 and 0.5 <= row.share <= 1.0


def test_reaches_the_table_cannot_use_are_counted_by_reason() -> None:
    """A reach with no grid point (point 0, as imported) and one without
    labels stay out of the demonstrations' table, and are counted apart."""
    demos = synthesize(2, subjects=1, trials=1)
    first, second, *rest = demos.trials
    mixed = DemoSet(
        demos.subjects, [first._replace(point=0), second._replace(labels=None), *rest]
    )
    assert left_out(mixed, "right") == LeftOut(no_point=1, no_labels=1, of=16)
    assert sum(row.trials for row in demo_rows(mixed, "right")) == 14
    assert left_out(demos, "right") == LeftOut(0, 0, 16)
    assert left_out(demos, "right").total == 0
    assert left_out(mixed, "right").describe() == (
        "1 has no grid point (point 0, as recorded reaches are imported) "
        "and 1 has no primitive labels"
    )


def test_a_table_is_of_one_arms_demonstrations() -> None:
    """A file of both arms was pooled into either arm's table without a
    word: each table takes its own arm's reaches and counts the others'."""
    right = synthesize(2, subjects=1, trials=1)
    left = [t._replace(arm=Side.LEFT, labels=["E_R W_P"] * 5) for t in right.trials]
    both = DemoSet(right.subjects, [*right.trials, *left[:3]])
    assert demo_rows(both, "right") == demo_rows(right, "right")
    assert left_out(both, "right") == LeftOut(0, 0, 19, other_arm=3)
    assert left_out(both, "right").describe() == "3 are of the other arm"
    only_left = demo_rows(both, "left")
    assert [r.trials for r in only_left] == [1, 1, 1]
    assert {tuple(r.sequence) for r in only_left} == {("E_R W_P",)}
    assert left_out(both, "left").total == 16
