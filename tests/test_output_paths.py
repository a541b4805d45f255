"""Files written under partial names and renamed to theirs, or not at all."""

from __future__ import annotations

import contextlib
import os
import resource
import signal
import stat
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from shared.errors import InvalidInputError
from shared.output_paths import (
    check_output_file,
    check_output_folder,
    replaced_together,
    try_output_folder,
    write_output_text,
)

NAMES = ("result.json", "result.md", "result.png")


@pytest.fixture
def older(tmp_path: Path) -> list[Path]:
    """An older set of the three files, each holding ``older <name>``."""
    paths = [tmp_path / name for name in NAMES]
    for path in paths:
        path.write_text(f"older {path.name}")
    return paths


def contents(folder: Path) -> dict[str, str]:
    """Every file in ``folder`` by name, with its text."""
    return {path.name: path.read_text() for path in sorted(folder.iterdir())}


def test_a_whole_set_replaces_the_older_one(older: list[Path]) -> None:
    """Once the block has written every partial file, each takes its name."""
    with replaced_together(older) as partials:
        for partial in partials:
            partial.write_text(f"newer {partial.name}")
    assert contents(older[0].parent) == {n: f"newer {n}.partial" for n in NAMES}


def test_a_failure_in_the_block_leaves_the_older_set(older: list[Path]) -> None:
    """Ctrl-C after two of three files: nothing replaced, no partial file left."""
    with pytest.raises(KeyboardInterrupt), replaced_together(older) as partials:
        partials[0].write_text("newer")
        partials[1].write_text("newer")
        raise KeyboardInterrupt
    assert contents(older[0].parent) == {n: f"older {n}" for n in NAMES}


def test_ctrl_c_between_two_renames_comes_after_the_last(
    older: list[Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A real SIGINT to this process right after the first rename: it came
    out there, the set left one file new and two older, claiming to be
    whole; now it is taken after the last rename, the set all new."""
    rename = os.replace

    def rename_then_ctrl_c(source: str | Path, target: str | Path) -> None:
        rename(source, target)
        if Path(target).name == NAMES[0]:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(os, "replace", rename_then_ctrl_c)
    with pytest.raises(KeyboardInterrupt), replaced_together(older) as partials:
        for partial in partials:
            partial.write_text("newer")
    monkeypatch.undo()
    assert contents(older[0].parent) == {n: "newer" for n in NAMES}
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_folder_in_a_files_place_leaves_the_older_set(older: list[Path]) -> None:
    """A folder where the last file goes: a typed error naming it, before any
    file is renamed, and no partial file left."""
    older[-1].unlink()
    older[-1].mkdir()
    with pytest.raises(InvalidInputError) as caught, replaced_together(older) as new:
        for partial in new:
            partial.write_text("newer")
    assert caught.value.message == f"cannot write {older[-1]}: Is a directory"
    assert caught.value.field == "out"
    older[-1].rmdir()
    assert contents(older[0].parent) == {n: f"older {n}" for n in NAMES[:-1]}


def test_a_failed_write_names_the_file_asked_for(older: list[Path]) -> None:
    """A write that fails inside the block (a folder stands at a partial
    name, as a full disk would fail it) named 'result.md.partial'; the
    error names result.md, and the older set stays whole."""
    partial_md = older[1].with_name(older[1].name + ".partial")
    partial_md.mkdir()
    with pytest.raises(InvalidInputError) as caught, replaced_together(older) as new:
        for partial in new:
            partial.write_text("newer")
    assert caught.value.message == f"cannot write {older[1]}: Is a directory"
    partial_md.rmdir()
    assert contents(older[0].parent) == {n: f"older {n}" for n in NAMES}


def test_two_writers_of_one_set_take_turns(
    older: list[Path], caplog: pytest.LogCaptureFixture
) -> None:
    """Two runs writing one set into one folder at once (two ``armplan
    experiment handover --out DIR``): the second shared the first's partial
    files, renamed them, and the first failed "No such file or directory",
    the folder left with a mix of both runs. Now the second waits for the
    first's set, saying so, and replaces it whole; neither fails."""
    written, go = threading.Event(), threading.Event()
    failed: list[str] = []

    def write(text: str, hold: bool) -> None:
        try:
            with replaced_together(older) as partials:
                for partial in partials:
                    partials.write_text(partial, text)
                if hold:
                    written.set()
                    go.wait(timeout=60)
        except InvalidInputError as error:
            failed.append(f"{text}: {error.message}")

    first = threading.Thread(target=write, args=("first", True))
    first.start()
    assert written.wait(timeout=60)
    second = threading.Thread(target=write, args=("second", False))
    second.start()
    second.join(timeout=2)  # it used to be done by now, the first's files taken
    go.set()
    first.join(timeout=60)
    second.join(timeout=60)
    assert failed == []
    assert contents(older[0].parent) == {n: "second" for n in NAMES}
    waits = [r.getMessage() for r in caplog.records if r.name == "armplan.output"]
    folder = older[0].parent
    assert waits == [f"waiting for another armplan run writing into {folder} to finish"]


def _small_files() -> None:
    """In the child: files of at most 4 kB (``ulimit -f``), the signal ignored
    so that a longer write fails with EFBIG instead of killing it."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))


def test_a_set_written_while_writing_another_in_its_folder(
    older: list[Path],
) -> None:
    """One process writing a second set into the folder while it writes a
    first: the second waited for the folder lock the first held, forever.
    Now both are written."""
    code = (
        "import sys; from pathlib import Path; "
        "from shared.output_paths import replaced_together\n"
        "a, b = Path(sys.argv[1]), Path(sys.argv[2])\n"
        "with replaced_together([a]) as outer:\n"
        "    outer.write_text(outer[0], 'outer')\n"
        "    with replaced_together([b]) as inner:\n"
        "        inner.write_text(inner[0], 'inner')\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(older[0]), str(older[1])],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    assert contents(older[0].parent) == {
        NAMES[0]: "outer",
        NAMES[1]: "inner",
        NAMES[2]: f"older {NAMES[2]}",
    }


def test_two_writers_of_one_file_take_turns(tmp_path: Path) -> None:
    """Two runs writing one file at once (two ``armplan fit -o model.json``)
    shared ``model.json.partial``: one renamed the other's, half written,
    into place, and the other failed "No such file or directory"."""
    path = tmp_path / "model.json"
    failed: list[str] = []

    def write(text: str) -> None:
        for _ in range(20):
            try:
                write_output_text(path, text * 1_000_000)
            except InvalidInputError as error:
                failed.append(error.message)

    writers = [threading.Thread(target=write, args=(c,)) for c in "ab"]
    for writer in writers:
        writer.start()
    for writer in writers:
        writer.join(timeout=120)
    assert failed == []
    assert path.read_text() in ("a" * 1_000_000, "b" * 1_000_000)
    assert [p.name for p in tmp_path.iterdir()] == [path.name]


def test_a_text_cut_short_leaves_the_older_file_whole(tmp_path: Path) -> None:
    """write_output_text of 10 kB in a process allowed 4 kB files: the error
    names the file and the reason, the older file keeps its text, and no
    partial file is left. It used to be written in place: the older file
    was cut to the first 4 kB of the new text."""
    path = tmp_path / "play.py"
    path.write_text("older\n")
    code = (
        "import sys\n"
        "from shared.output_paths import write_output_text\n"
        "from shared.errors import InvalidInputError\n"
        "try:\n"
        "    write_output_text(sys.argv[1], 'x' * 10_000)\n"
        "except InvalidInputError as error:\n"
        "    print(error.message)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(path)],
        capture_output=True,
        text=True,
        timeout=60,
        preexec_fn=_small_files,
        check=True,
    )
    assert done.stdout == f"cannot write {path}: File too large\n"
    assert path.read_text() == "older\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["play.py"]


def test_a_link_to_a_file_in_no_folder_is_refused_up_front(tmp_path: Path) -> None:
    """``-o latest.mcap``, a link to ``gone/run.mcap`` whose folder is
    missing: the check passed, the work ran, and the write through the link
    failed naming its partial file ("cannot create .../gone/run.mcap.partial").
    A link to a file yet to be made in an existing folder is written."""
    link = tmp_path / "latest.mcap"
    link.symlink_to(Path("gone") / "run.mcap")
    with pytest.raises(InvalidInputError) as caught:
        check_output_file(link)
    target = tmp_path / "gone" / "run.mcap"
    assert caught.value.message == (
        f"cannot write {link}: No such file or directory (it links to {target})"
    )
    (tmp_path / "gone").mkdir()
    write_output_text(check_output_file(link), "newer")
    assert link.is_symlink() and target.read_text() == "newer"


def test_a_replaced_file_keeps_its_mode_and_its_link(tmp_path: Path) -> None:
    """An executable play.py reached through a symbolic link: the new text
    replaces the file the link names, which keeps its mode (0o750), and
    the link stays a link."""
    path = tmp_path / "play.py"
    path.write_text("older")
    path.chmod(0o750)
    link = tmp_path / "latest.py"
    link.symlink_to(path.name)
    assert write_output_text(link, "newer") == link
    assert link.is_symlink() and link.read_text() == "newer"
    assert stat.S_IMODE(path.stat().st_mode) == 0o750
    assert sorted(p.name for p in tmp_path.iterdir()) == ["latest.py", "play.py"]


def test_a_fifo_is_written_into_not_replaced(tmp_path: Path) -> None:
    """An output path that is no regular file (a FIFO here; /dev/null,
    /dev/stdout alike) gets the text: it was replaced by a regular file, and
    whatever read the FIFO got nothing."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got: list[str] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_text()))
    reader.start()
    write_output_text(fifo, "keys\n")
    reader.join(timeout=10)
    assert got == ["keys\n"]
    assert stat.S_ISFIFO(fifo.stat().st_mode)
    assert list(tmp_path.iterdir()) == [fifo]


def test_dev_stdout_into_a_pipe_is_written() -> None:
    """``-o /dev/stdout | ...``: the link leads to a pipe with no name to put
    a file beside; it was refused "No such file or directory"."""
    code = (
        "from shared.output_paths import write_output_text; "
        "write_output_text('/dev/stdout', 'keys\\n')"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60
    )
    assert (done.returncode, done.stdout) == (0, "keys\n"), done.stderr


def test_dev_stdout_redirected_to_a_file_is_written_into(tmp_path: Path) -> None:
    """``-o /dev/stdout >> run.log``: the link leads to the log through
    ``/proc``; a new file was renamed over the log, and what the shell wrote
    after went to the replaced one, lost. Now the log is written into, as by
    any program: it stays the file the shell holds."""
    log = tmp_path / "run.log"
    log.write_text("earlier\n")
    inode = log.stat().st_ino
    code = (
        "from shared.output_paths import write_output_text; "
        "write_output_text('/dev/stdout', 'keys\\n'); print('after')"
    )
    with log.open("a") as stream:
        done = subprocess.run(
            [sys.executable, "-c", code], stdout=stream, text=True, timeout=60
        )
    assert done.returncode == 0
    assert log.stat().st_ino == inode
    assert log.read_text().endswith("keys\nafter\n")
    assert [p.name for p in tmp_path.iterdir()] == [log.name]


def test_a_write_cut_short_in_a_set_names_the_file(older: list[Path]) -> None:
    """The second of three files, 10 kB, in a process allowed 4 kB files:
    write() fails with EFBIG and no file name (as on a full disk). It was
    that raw OSError, a traceback out of ``armplan demo``; now the typed
    error names result.md (not its partial name), the older set stays
    whole and no partial file is left."""
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "from shared.errors import InvalidInputError\n"
        "from shared.output_paths import replaced_together\n"
        "paths = [Path(p) for p in sys.argv[1:]]\n"
        "try:\n"
        "    with replaced_together(paths) as partials:\n"
        "        partials.write_text(partials[0], 'newer')\n"
        "        partials.write_text(partials[1], 'x' * 10_000)\n"
        "        partials.write_text(partials[2], 'newer')\n"
        "except InvalidInputError as error:\n"
        "    print(error.message, error.field)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, *map(str, older)],
        capture_output=True,
        text=True,
        timeout=60,
        preexec_fn=_small_files,
        check=False,
    )
    assert (done.returncode, done.stdout) == (
        0,
        f"cannot write {older[1]}: File too large out\n",
    ), done.stderr
    assert contents(older[0].parent) == {n: f"older {n}" for n in NAMES}


@contextlib.contextmanager
def tmpfs(folder: Path, options: str) -> Iterator[Path]:
    """``folder`` made and a tmpfs mounted on it with ``options``, unmounted
    after; skipped where mounting is not permitted (no root, a container
    without the privilege)."""
    folder.mkdir()
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)],
        capture_output=True,
        text=True,
        timeout=30,
        check=False,
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs: {mounted.stderr.strip()}")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], timeout=30, check=True)


@pytest.fixture
def full_disk(tmp_path: Path) -> Iterator[Path]:
    """A folder on a 64 kB tmpfs."""
    with tmpfs(tmp_path / "tiny", "size=64k") as folder:
        yield folder


def test_a_folder_tried_leaves_none_of_its_parents(tmp_path: Path) -> None:
    """``--out tiny/a/b/c`` on a file system with inodes for two folders:
    the check up front made ``a`` and ``b``, failed at ``c`` and left both
    behind, though it promises to leave no trace."""
    with tmpfs(tmp_path / "tiny", "size=64k,nr_inodes=3") as folder:
        out = folder / "a" / "b" / "c"
        with pytest.raises(InvalidInputError) as caught:
            try_output_folder(out)
        assert caught.value.message == (
            f"cannot write into {out} (--out): No space left on device"
        )
        assert list(folder.iterdir()) == []


def test_a_full_disk_names_the_file(full_disk: Path) -> None:
    """A real full disk (ENOSPC from write(), no file name): the typed error
    names the file and says 'No space left on device'; nothing is left."""
    paths = [full_disk / name for name in NAMES]
    with pytest.raises(InvalidInputError) as caught, replaced_together(paths) as new:
        new.write_text(new[0], "x" * 200_000)
    assert caught.value.message == f"cannot write {paths[0]}: No space left on device"
    assert list(full_disk.iterdir()) == []


@pytest.fixture
def read_only(tmp_path: Path) -> Iterator[Path]:
    """A folder on a read-only tmpfs."""
    with tmpfs(tmp_path / "ro", "ro,size=64k") as folder:
        yield folder


def test_a_read_only_mount_is_named_so(read_only: Path) -> None:
    """--out or -o on a read-only mount (a container's volume) said
    "Permission denied", which no chmod mends; now the OS's words for it."""
    with pytest.raises(InvalidInputError) as caught:
        check_output_folder(read_only / "results")
    assert caught.value.message == (
        f"cannot write into {read_only / 'results'} (--out): "
        f"{read_only}: Read-only file system"
    )
    with pytest.raises(InvalidInputError) as caught:
        check_output_file(read_only / "model.json")
    assert caught.value.message == (
        f"cannot write {read_only / 'model.json'}: Read-only file system"
    )


def test_a_dash_for_standard_output_is_refused_with_the_way_to_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``-o -`` (standard output, to most tools) wrote a file named ``-`` in
    the working folder; it is refused, saying how to write to standard
    output, and ``./-`` still names such a file on purpose."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(InvalidInputError, match="give /dev/stdout to") as caught:
        check_output_file("-")
    assert caught.value.field == "output"
    assert check_output_file("./-") == Path("-")
    assert not (tmp_path / "-").exists()
