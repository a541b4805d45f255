"""A misspelt key is named first, with the field it may have meant.

A key that is no field beside a missing one in the same object is a
misspelt key. The error used to be the missing field's, the key hidden
behind "and 1 more problem" (``{"phase": ...}`` in a task file said
"phases: Field required; and 1 more problem").
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from armplan.demo.task import TaskFile, load_task
from shared.errors import InvalidInputError
from shared.messages import parse
from shared.messages.base import _alike

TARGET = {"position": [0.14, -0.1, 0.06]}


@pytest.mark.parametrize(
    ("data", "field", "message"),
    [
        (
            {"phase": [{"name": "a", "targets": [TARGET]}]},
            "phase",
            "phase is not a field (did you mean phases?)",
        ),
        (
            {"phases": [{"name": "a", "target": [TARGET]}]},
            "phases.0.target",
            "phases.0.target is not a field (did you mean phases.0.targets?)",
        ),
        (
            {"phases": [{"name": "a", "targest": [TARGET], "says": 1, "zzz": 0}]},
            "phases.0.targest",
            "phases.0.targest is not a field (did you mean phases.0.targets?); "
            "and 2 more problems",
        ),
    ],
    ids=["top", "nested", "closest-of-two"],
)
def test_a_misspelt_key_in_a_task_file_is_named(
    tmp_path: Path, data: dict[str, object], field: str, message: str
) -> None:
    """A real task file with the key misspelt: the error names that key."""
    path = tmp_path / "task.json"
    path.write_text(json.dumps(data))
    with pytest.raises(InvalidInputError) as caught:
        load_task(path)
    assert f"{path}: invalid TaskFile: {message} (see " in caught.value.message
    with pytest.raises(InvalidInputError) as parsed:
        parse(TaskFile, data)
    assert parsed.value.field == field


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"phases": []}, "phases: List should have at least 1 item"),
        (
            {"phases": [{"name": "a", "targets": [{**TARGET, "dwel": 0.5}]}]},
            "phases.0.targets.0.dwel: Extra inputs are not permitted (got 0.5)",
        ),
        ({}, "phases: Field required"),
        (
            {"phases": [{"name": "reach", "note": "TODO add targets"}]},
            "phases.0.targets: Field required; and 1 more problem",
        ),
        (
            {"phases": [{"name": "a", "targets": [{"dwell": 0.5, "comment": "x"}]}]},
            "phases.0.targets.0.position: Field required; and 1 more problem",
        ),
    ],
    ids=["no-extra", "extra-alone", "missing-alone", "unrelated", "unrelated-deep"],
)
def test_other_problems_are_told_as_before(
    data: dict[str, object], message: str
) -> None:
    """An extra key with no field missing beside it, a missing field with no
    extra key, or one with an unrelated extra key (a ``note`` is no
    misspelt ``targets``): the first problem, worded as pydantic words it."""
    with pytest.raises(InvalidInputError) as caught:
        parse(TaskFile, data)
    assert caught.value.message.startswith(f"invalid TaskFile: {message}")


@pytest.mark.parametrize(
    ("key", "field", "alike"),
    [
        ("phase", "phases", True),
        ("target", "targets", True),
        ("targest", "targets", True),
        ("pos", "position", True),
        ("Dwell", "dwell", True),
        ("note", "targets", False),
        ("comment", "trajectory", False),
        ("comment", "position", False),
        ("x", "xyz", False),
    ],
)
def test_a_key_is_taken_for_a_misspelling_only_if_alike(
    key: str, field: str, alike: bool
) -> None:
    """A "did you mean" names only a key close to the missing field."""
    assert _alike(key, field) is alike
