"""A partial file an earlier demo left (killed while it wrote) is its own.

The demo writes ``trajectory.json`` under ``trajectory.json.partial`` first
(``replaced_together``); a SIGKILL in between leaves the partial file. The
next run refused the folder, though the earlier run's list names
``trajectory.json``. Real files, through ``replace_earlier_run``.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from armplan.demo.earlier_run import LIST_FILE, replace_earlier_run
from shared.errors import InvalidInputError

NAMES = ("trajectory.json", "report.json", "logs/services.log")


def test_an_earlier_runs_partial_file_is_removed(tmp_path: Path) -> None:
    """A run killed while writing: its list, trajectory.json.partial and a
    log. The next run removes the partial file and the log; it was refused
    "stands where the demo writes trajectory.json first"."""
    out = tmp_path / "kw"
    (out / "logs").mkdir(parents=True)
    replace_earlier_run(out, NAMES)  # the killed run's claim: its list
    (out / "logs" / "services.log").write_text("started\n")
    (out / "trajectory.json.partial").write_text('{"arm": "ri')  # cut short
    replace_earlier_run(out, NAMES)
    files = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert files == {LIST_FILE}


def test_a_partial_file_without_a_list_is_refused_and_kept(tmp_path: Path) -> None:
    """No earlier run's list: the partial file may be the user's; refused
    naming it, and nothing removed."""
    out = tmp_path / "here"
    out.mkdir()
    (out / "trajectory.json.partial").write_text("mine\n")
    with pytest.raises(InvalidInputError) as caught:
        replace_earlier_run(out, NAMES)
    assert caught.value.message == (
        f"cannot write into {out} (--out): {out / 'trajectory.json.partial'} stands "
        "where the demo writes trajectory.json first; move it away or give "
        "another --out"
    )
    assert (out / "trajectory.json.partial").read_text() == "mine\n"
    assert sorted(p.name for p in out.iterdir()) == ["trajectory.json.partial"]


def test_a_listed_partial_name_that_is_a_folder_is_refused(tmp_path: Path) -> None:
    """A folder at a listed name's partial name is no file a run left: refused,
    and the earlier run's files are not removed either."""
    out = tmp_path / "here"
    out.mkdir()
    replace_earlier_run(out, NAMES)
    (out / "report.json").write_text("{}\n")
    (out / "report.json.partial").mkdir()
    with pytest.raises(InvalidInputError, match=r"report\.json\.partial stands where"):
        replace_earlier_run(out, NAMES)
    assert (out / "report.json").read_text() == "{}\n"
