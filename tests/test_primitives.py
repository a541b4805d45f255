"""The ten movement primitives: names from matrices, joints, tasks, methods."""

from __future__ import annotations

import pytest

from shared.errors import InvalidInputError, UnknownPrimitiveError
from shared.primitives import (
    BY_NAME,
    MOTION_PRIMITIVES,
    PRIMITIVES,
    IKMethod,
    PrimitiveType,
    Task,
    get_primitive,
    matrix_from_mp_form,
    mp_form,
)

# The paper's Table 1 names, in order.
TABLE_1 = [
    "S_R E_P W_P",
    "E_R W_P",
    "S_R E_PR W_P",
    "S_R E_P W_PR",
    "S_R W_P",
    "S_R W_PR",
    "E_R W_PR",
    "S_R E_PR W_PR",
    "S_R E_P W_R",
    "W_R",
]

# The eight matrices printed in Section II.C, as printed.
PRINTED = {
    "S_R E_P W_P": [[0, 1, 1], [1, 0, 0], [0, 0, 0]],
    "E_R W_P": [[0, 0, 1], [0, 1, 0], [0, 0, 0]],
    "S_R E_PR W_P": [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
    "S_R E_P W_PR": [[0, 0, 0], [1, 0, 0], [0, 1, 1]],  # the paper's typo
    "S_R W_P": [[0, 0, 1], [1, 0, 0], [0, 0, 0]],
    "S_R W_PR": [[0, 0, 0], [1, 0, 0], [0, 0, 1]],
    "E_R W_PR": [[0, 0, 0], [0, 1, 0], [0, 0, 1]],
    "S_R E_PR W_PR": [[0, 0, 0], [1, 0, 0], [0, 1, 1]],
}

# The SPEC's primitive table: active NAO joints (0 ShoulderPitch .. 4 WristYaw).
SPEC_ACTIVE = {
    "S_R E_P W_P": (0, 1, 2),
    "E_R W_P": (3,),
    "S_R E_PR W_P": (0, 1, 2, 3),
    "S_R E_P W_PR": (0, 1, 2, 4),
    "S_R W_P": (2,),
    "S_R W_PR": (2, 4),
    "E_R W_PR": (3, 4),
    "S_R E_PR W_PR": (0, 1, 2, 3, 4),
    "S_R E_P W_R": (0, 1, 2, 4),
    "W_R": (4,),
}
# The one documented deviation: on NAO, holding the wrist exactly while the
# elbow swivels needs ElbowRoll too (the shoulder is not spherical).
DEVIATIONS = {"S_R E_P W_R": (0, 1, 2, 3, 4)}


def test_names_are_computed_from_matrices_in_table_order() -> None:
    """a e j of each catalogue matrix spells Table 1's names, in order."""
    assert [p.name for p in PRIMITIVES] == TABLE_1


def test_printed_matrices_spell_their_names_except_the_typo() -> None:
    """Seven printed matrices spell their own name; S_R E_P W_PR's is a typo."""
    for name, matrix in PRINTED.items():
        if name == "S_R E_P W_PR":
            assert mp_form(matrix) == "S_R E_PR W_PR"
        else:
            assert mp_form(matrix) == name
            assert [list(r) for r in BY_NAME[name].matrix] == matrix


def test_matrix_and_name_are_inverse() -> None:
    """matrix_from_mp_form undoes mp_form for all ten primitives."""
    for p in PRIMITIVES:
        assert matrix_from_mp_form(p.name) == p.matrix
        assert mp_form(matrix_from_mp_form(p.name)) == p.name


def test_all_matrices_are_distinct() -> None:
    """No two primitives share a matrix."""
    assert len({p.matrix for p in PRIMITIVES}) == 10


def test_active_joints_follow_the_spec_table() -> None:
    """Each primitive moves exactly the SPEC's joints, but for the documented one."""
    assert {p.name: p.active for p in PRIMITIVES} == SPEC_ACTIVE | DEVIATIONS


def test_active_joints_follow_from_the_matrix() -> None:
    """S_R moves the shoulder joints (only ElbowYaw if the elbow stays put), E_R
    ElbowRoll, W_R WristYaw: the SPEC's table follows from the matrices."""
    for p in PRIMITIVES:
        terms = dict(p.terms)
        expected: set[int] = set()
        if terms.get("S") == "R":
            expected |= {0, 1, 2} if "E" in terms else {2}
        if terms.get("E") in ("R", "PR"):
            expected.add(3)
        if terms.get("W") in ("R", "PR"):
            expected.add(4)
        if p.name in DEVIATIONS:
            expected.add(3)
        assert set(p.active) == expected, p.name


def test_types_tasks_and_methods() -> None:
    """Eight motion primitives, two function primitives; methods as in the SPEC."""
    assert len(MOTION_PRIMITIVES) == 8
    assert [p.name for p in PRIMITIVES if p.kind is PrimitiveType.FMP] == [
        "S_R E_P W_R",
        "W_R",
    ]
    assert BY_NAME["E_R W_P"].ik is IKMethod.ELBOW_TRIANGLE
    assert BY_NAME["S_R W_P"].ik is IKMethod.SHOULDER_ROTATION
    assert {p.name for p in PRIMITIVES if p.ik is IKMethod.GPM_TPE} == {
        "S_R E_P W_P",
        "S_R E_PR W_P",
    }
    assert all(p.task is Task.POSE for p in PRIMITIVES if p.ik is IKMethod.GPM_GRASP)
    assert all(
        p.orients_wrist == (p.task in (Task.POSE, Task.HOLD, Task.TURN))
        for p in PRIMITIVES
    )


def test_lookup_tolerates_spacing_and_rejects_unknown_names() -> None:
    """get_primitive ignores extra spaces and names the known primitives on error."""
    assert get_primitive("  S_R   E_PR W_P ").name == "S_R E_PR W_P"
    with pytest.raises(UnknownPrimitiveError, match="unknown movement primitive 'X_Y'"):
        get_primitive("X_Y")


@pytest.mark.parametrize(
    "matrix",
    [
        [[1, 1], [0, 0]],
        [[2, 0, 0], [0, 0, 0], [0, 0, 0]],
        [[1, 0, 0], [1, 0, 0], [0, 0, 0]],
    ],
)
def test_malformed_matrices_are_rejected(matrix: list[list[int]]) -> None:
    """A matrix not 3x3 of 0/1 with one attribute per joint is an InvalidInputError."""
    with pytest.raises(InvalidInputError):
        mp_form(matrix)
