"""``--out DIR`` of ``armplan certs``, ``demo`` and ``faults``; ``certs --host``;
the log a failed ``armplan demo`` start points to.

A folder that cannot be one is refused with the path and the reason, exit
code 1, before any process starts or any file is written.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from armplan.cli.main import main
from shared.errors import InvalidInputError

COMMANDS = ("certs", "demo", "faults")


def armplan(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    """Exit code and standard error of ``armplan ARGS``, run in this process."""
    code = main(list(args))
    return code, capsys.readouterr().err


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An empty current folder (a relative --out lands in it)."""
    folder = tmp_path / "here"
    folder.mkdir()
    monkeypatch.chdir(folder)
    return folder


@pytest.mark.parametrize("command", COMMANDS)
def test_a_file_as_out_is_refused(
    command: str, here: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out FILE names the file and says it is no folder (was FileExistsError)."""
    (here / "results").write_text("kept\n")
    code, err = armplan(capsys, command, "--out", "results")
    assert code == 1
    assert err == (
        "armplan: error: cannot write into results (--out): "
        "it is a file, not a folder\n"
    )
    assert (here / "results").read_text() == "kept\n"


@pytest.mark.parametrize("command", COMMANDS)
def test_an_out_under_a_file_is_refused(
    command: str, here: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out FILE/sub names the file in the way."""
    (here / "results").write_text("kept\n")
    code, err = armplan(capsys, command, "--out", "results/sub")
    assert code == 1
    assert err == (
        "armplan: error: cannot write into results/sub (--out): "
        "results is a file, not a folder\n"
    )


@pytest.mark.parametrize("command", COMMANDS)
def test_a_name_too_long_is_refused(
    command: str, here: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A folder name over 255 bytes: the OS's reason, not OSError's traceback."""
    name = "a" * 300
    code, err = armplan(capsys, command, "--out", name)
    assert code == 1
    assert err == (
        f"armplan: error: cannot write into {name} (--out): File name too long\n"
    )
    assert list(here.iterdir()) == []


@pytest.mark.parametrize("command", ["demo", "faults"])
def test_a_folder_the_system_refuses_is_an_error(command: str) -> None:
    """/sys takes no folder (EPERM even for root, which access() lets pass):
    exit 1 naming the path, not a PermissionError traceback."""
    out = "/sys/armplan-out-test"
    result = subprocess.run(
        [sys.executable, "-m", "armplan", command, "--out", out],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 1, result.stderr
    assert result.stderr.startswith(
        f"armplan: error: cannot write into {out} (--out): "
    )
    assert "Traceback" not in result.stderr
    assert not Path(out).exists()


@pytest.mark.parametrize("command", COMMANDS)
def test_an_empty_out_is_refused(
    command: str, here: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out "" is refused; certs wrote into the current folder, demo too."""
    code, err = armplan(capsys, command, "--out", "")
    assert code == 1
    assert err == (
        "armplan: error: --out is empty: name a folder (. for the current one)\n"
    )
    assert list(here.iterdir()) == []


def test_faults_refuses_a_folder_holding_a_recording(
    here: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A demo folder's session.mcap (from a real NAO, say) was silently
    replaced by the suite's recording: now the folder is refused, naming
    the files, before anything starts, and they are left as they were."""
    (here / "logs").mkdir()
    kept = {"session.mcap": b"a demo's recording", "logs/services.log": b"old\n"}
    kept |= {"session-2.mcap": b"an earlier suite's", "logs/recorder-2.log": b"x"}
    for name, data in kept.items():
        (here / name).write_bytes(data)
    (here / "session-old.mcap").write_bytes(b"not a name the suite writes")
    code, err = armplan(capsys, "faults", "--out", ".", "--requests", "3")
    assert code == 1
    assert err == (
        "armplan: error: cannot write into . (--out): it holds session.mcap, "
        "logs/services.log, session-2.mcap, logs/recorder-2.log, which armplan "
        "faults would replace or add to; give --overwrite to replace them, or "
        "give another --out\n"
    )
    assert {n: (here / n).read_bytes() for n in kept} == kept
    assert not (here / "zenoh.json5").exists()


def test_faults_overwrite_clears_an_earlier_runs_files_only(here: Path) -> None:
    """--overwrite: the suite's names are removed before it starts (no old
    session-5.mcap or log lines mixed into this run's); other files stay."""
    from armplan.faults.system import FaultSystem

    (here / "logs").mkdir()
    for name in ("session.mcap", "session-5.mcap", "sim.jsonl", "logs/bridge.log"):
        (here / name).write_text("earlier\n")
    (here / "notes.txt").write_text("mine\n")
    with pytest.raises(InvalidInputError, match="give --overwrite"):
        FaultSystem(here)
    system = FaultSystem(here, overwrite=True)  # prepared, not started
    assert system.out == here
    left = sorted(p.relative_to(here).as_posix() for p in here.rglob("*"))
    assert left == ["logs", "notes.txt", "zenoh.json5"]


@pytest.mark.parametrize("host", ["", "bad host", "under_score", "999.1.1.1", "10.0.0"])
def test_a_bad_host_writes_nothing(
    host: str, here: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """certs --host checks every name before the authority is made (ca.key
    and ca.pem were left behind); a mistyped IPv4 address (999.1.1.1) was
    taken for a DNS name."""
    code, err = armplan(capsys, "certs", "--out", "c3", "--host", host)
    assert code == 1
    assert err == (
        f"armplan: error: host {host!r} is neither a DNS name nor an IP address\n"
    )
    assert list(here.iterdir()) == []


@pytest.fixture
def busy_endpoint(busy_port: int) -> str:
    """A Zenoh endpoint on 127.0.0.1 whose port another socket listens on."""
    return f"tcp/127.0.0.1:{busy_port}"


def test_a_failed_demo_start_names_the_log_to_read(
    tmp_path: Path, busy_endpoint: str
) -> None:
    """The router cannot listen on a port in use: the error gives the log's
    path (it said only "see its log"), and that log tells why."""
    out = tmp_path / "demo"
    demo = ["demo", "--out", str(out), "--listen", busy_endpoint, "--no-record"]
    done = subprocess.run(
        [sys.executable, "-m", "armplan", *demo],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    log = out / "logs" / "services.log"
    assert done.returncode == 1
    assert done.stderr == (
        "armplan: error: service 'router' is unavailable: its process exited "
        f"with code 1 while starting (see its log {log})\n"
    )
    assert "Address already in use" in log.read_text()
    # the endpoint came from --listen, not from config/zenoh.json5 (it said)
    assert "Zenoh configuration --listen/--connect (listen/endpoints)" in (
        log.read_text()
    )
