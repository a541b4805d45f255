"""``armplan demo --out DIR`` in a folder that holds other files.

The demo replaces only what an earlier demo wrote: the user's files in DIR
(``logs/nao.log``, their own ``play.py``) are left alone, or the run is
refused before anything starts. Runs here fail fast on purpose (their
router's port is taken), which is when the old demo had already deleted
the user's files.
"""

from __future__ import annotations

import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from armplan.demo.earlier_run import LIST_FILE, replace_earlier_run
from shared.errors import InvalidInputError

#: Longest a demo whose router cannot start may take to fail [s].
FAIL_TIMEOUT = 90.0


@pytest.fixture
def busy_endpoint() -> Iterator[str]:
    """A loopback endpoint whose port another socket listens on."""
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        yield f"tcp/127.0.0.1:{taken.getsockname()[1]}"


def demo(out: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """``armplan demo --out OUT ARGS``, run to its end."""
    return subprocess.run(
        [sys.executable, "-m", "armplan", "demo", "--out", str(out), *args],
        capture_output=True,
        text=True,
        timeout=FAIL_TIMEOUT,
    )


def test_a_failed_run_keeps_the_users_logs_and_replaces_an_earlier_runs(
    tmp_path: Path, busy_endpoint: str
) -> None:
    """The user's logs/nao.log survives two runs; the second run removes the
    report the first one's list names (so no stale result is left)."""
    out = tmp_path / "here"
    (out / "logs").mkdir(parents=True)
    (out / "logs" / "nao.log").write_text("3 weeks of robot logs\n")
    first = demo(out, "--listen", busy_endpoint)
    assert first.returncode == 1, first.stderr
    assert (out / "logs" / "nao.log").read_text() == "3 weeks of robot logs\n"
    assert "report.json" in (out / LIST_FILE).read_text().splitlines()
    (out / "report.json").write_text("{}")  # as a run that got that far leaves it
    second = demo(out, "--listen", busy_endpoint)
    assert second.returncode == 1, second.stderr
    assert not (out / "report.json").exists()
    assert (out / "logs" / "nao.log").read_text() == "3 weeks of robot logs\n"


@pytest.mark.parametrize("name", ["play.py", "logs/services.log"])
def test_a_file_no_demo_wrote_is_refused_and_kept(tmp_path: Path, name: str) -> None:
    """A file of an output's name that no earlier demo listed: exit 1 naming
    it, before anything starts (no log written), and the file unchanged."""
    out = tmp_path / "here"
    path = out / name
    path.parent.mkdir(parents=True)
    path.write_text("mine\n")
    result = demo(out)
    assert result.returncode == 1, result.stderr
    assert result.stderr == (
        f"armplan: error: {out} (--out) holds {name}, which the demo would "
        f"replace, and no {LIST_FILE} list says the demo wrote it: move it or "
        "choose another --out\n"
    )
    assert path.read_text() == "mine\n"
    files = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert files == {name}


def test_a_folder_an_older_demo_wrote_is_replaced(
    tmp_path: Path, busy_endpoint: str
) -> None:
    """The default ./armplan-demo of a demo from before the list: only the
    demo's files, no list. Taken as an earlier run's (it was refused as 'not
    from an earlier armplan demo', which broke the README's first command
    after an upgrade); a stray file beside them keeps the refusal."""
    out = tmp_path / "armplan-demo"
    (out / "logs").mkdir(parents=True)
    for name in ("trajectory.json", "report.json", "logs/services.log"):
        (out / name).write_text("{}\\n")
    result = demo(out, "--listen", busy_endpoint)  # fails fast, after the claim
    assert "which the demo would replace" not in result.stderr
    assert not (out / "report.json").exists()
    assert (out / LIST_FILE).exists()

    other = tmp_path / "mixed"
    (other / "logs").mkdir(parents=True)
    for name in ("trajectory.json", "report.json", "notes.txt"):
        (other / name).write_text("{}\\n")
    result = demo(other, "--listen", busy_endpoint)
    assert result.returncode == 1, result.stderr
    assert (
        f"{other} (--out) holds trajectory.json, which the demo would replace, and no "
        f"{LIST_FILE} list says the demo wrote it (the folder also holds "
        "notes.txt, so it is not just an older demo's output): move it or choose "
        "another --out" in result.stderr
    )
    assert (other / "report.json").read_text() == "{}\\n"


def test_a_file_where_the_demo_keeps_its_logs_is_refused(tmp_path: Path) -> None:
    """OUT/logs a file: one line naming it, before anything is written (it
    was a FileExistsError traceback, after the list had been written)."""
    out = tmp_path / "here"
    out.mkdir()
    (out / "logs").write_text("not a folder\n")
    result = demo(out)
    assert result.returncode == 1, result.stderr
    assert result.stderr == (
        f"armplan: error: cannot write into {out} (--out): {out / 'logs'} is not a "
        "folder and the demo writes its logs there; move it away or give another "
        "--out\n"
    )
    assert sorted(p.name for p in out.iterdir()) == ["logs"]


def test_a_partial_name_in_the_way_is_refused_before_anything_starts(
    tmp_path: Path,
) -> None:
    """OUT/report.json.partial (the name report.json is written under first):
    one line naming it, before anything starts. It was found only once the
    robot had played the task, whose outputs were then lost; a user's file
    of that name was overwritten and removed."""
    out = tmp_path / "here"
    (out / "report.json.partial").mkdir(parents=True)
    result = demo(out)
    assert result.returncode == 1, result.stderr
    assert result.stderr == (
        f"armplan: error: cannot write into {out} (--out): "
        f"{out / 'report.json.partial'} stands where the demo writes report.json "
        "first; move it away or give another --out\n"
    )
    assert sorted(p.name for p in out.iterdir()) == ["report.json.partial"]


def test_the_refusals_name_the_file_and_what_to_do(tmp_path: Path) -> None:
    """A folder whose list lacks the file, and a folder where the demo
    writes a file: one sentence each naming it and what to do; nothing
    touched. They read "PATH is not from an earlier armplan demo, and the
    demo would replace it; move it away ..." and "PATH is a folder, and ...".
    """
    names = ["trajectory.json", "play.py"]
    listed = tmp_path / "listed"
    listed.mkdir()
    (listed / LIST_FILE).write_text("trajectory.json\n")
    (listed / "play.py").write_text("mine\n")
    with pytest.raises(InvalidInputError) as raised:
        replace_earlier_run(listed, names)
    assert raised.value.message == (
        f"{listed} (--out) holds play.py, which the demo would replace, and its "
        f"{LIST_FILE} list does not say the demo wrote it: move it or choose "
        "another --out"
    )
    assert (listed / "play.py").read_text() == "mine\n"

    folder = tmp_path / "folder"
    (folder / "play.py").mkdir(parents=True)
    with pytest.raises(InvalidInputError) as raised:
        replace_earlier_run(folder, names, option="--into")
    assert raised.value.message == (
        f"{folder} (--into) holds a folder play.py, where the demo writes a file: "
        "move it or choose another --into"
    )
    assert sorted(p.name for p in folder.iterdir()) == ["play.py"]
