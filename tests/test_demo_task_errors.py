"""What a task file ``armplan demo --task`` cannot read is told to do."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from armplan.cli.main import main
from armplan.demo.task import DEFAULT_TASK, load_task
from shared.errors import InvalidInputError

#: What ``armplan plan --task`` takes: one PlanRequest.
PLAN_REQUEST = {"targets": [{"position": [0.12, -0.10, 0.05]}], "rate": 50}


def test_an_error_points_to_the_shipped_task_by_its_real_path(tmp_path: Path) -> None:
    """The shipped task's path, not its name alone: "see handover_task.json"
    named a file the user could not find (it is inside the package)."""
    missing = tmp_path / "nope.json"
    with pytest.raises(InvalidInputError) as refused:
        load_task(missing)
    assert DEFAULT_TASK.is_absolute() and DEFAULT_TASK.is_file()
    assert refused.value.message == (
        f"{missing}: cannot read task file {missing}: No such file or directory "
        f"(see {DEFAULT_TASK} for the form)"
    )


def test_a_plan_request_given_to_the_demo_says_which_command_takes_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A PlanRequest (``armplan plan --task``'s form) read "phases: Field
    required; and 1 more problem" alone; now it is named, as ``plan --task``
    names a demo task given to it."""
    path = tmp_path / "request.json"
    path.write_text(json.dumps(PLAN_REQUEST))
    out = tmp_path / "demo"
    assert main(["demo", "--task", str(path), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert (
        "(this file is a PlanRequest, for `armplan plan --task FILE`; `demo "
        f"--task` takes a demo task of phases: see {DEFAULT_TASK} for the form)"
    ) in err
    assert not out.exists()


@pytest.mark.parametrize(
    "fields",
    [{"phase": []}, {"phases": [], "rate": 50}, {"name": "x"}],
    ids=["misspelt", "phases", "no-request-key"],
)
def test_a_demo_task_with_a_mistake_is_not_called_a_plan_request(
    tmp_path: Path, fields: dict[str, object]
) -> None:
    """Only a file with no phases and a key of a PlanRequest's own gets the
    hint: a demo task's mistakes are its own."""
    path = tmp_path / "task.json"
    path.write_text(json.dumps(fields))
    with pytest.raises(InvalidInputError) as refused:
        load_task(path)
    assert "PlanRequest" not in refused.value.message
    assert refused.value.message.endswith(f"(see {DEFAULT_TASK} for the form)")


def test_a_task_file_with_a_byte_order_mark_is_read(tmp_path: Path) -> None:
    """The shipped task saved with a byte-order mark (Windows Notepad) was
    refused as "not valid JSON (... line 1 column 1)"; it reads as the
    shipped one."""
    marked = tmp_path / "marked.json"
    marked.write_text(DEFAULT_TASK.read_text(), encoding="utf-8-sig")
    assert marked.read_bytes().startswith(b"\xef\xbb\xbf")
    assert load_task(marked).phases == load_task(DEFAULT_TASK).phases


def test_a_task_file_with_a_key_written_twice_is_refused(tmp_path: Path) -> None:
    """A phase's "targets" written twice was read as the last alone: the
    robot would have played other targets than the file shows."""
    text = json.dumps(json.loads(DEFAULT_TASK.read_text()))
    first = '"targets": ['
    assert text.count(first) > 1
    extra = '"targets": [{"position": [0.12, -0.13, 0.05]}], '
    path = tmp_path / "twice.json"
    path.write_text(text.replace(first, extra + first, 1))
    with pytest.raises(InvalidInputError) as refused:
        load_task(path)
    assert refused.value.message.startswith(
        f"{path}: TaskFile: key 'targets' is written twice in one object; "
        "only the last would be read: keep one"
    )
