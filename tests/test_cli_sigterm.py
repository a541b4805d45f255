"""Every command unwinds on SIGTERM as on Ctrl-C (``armplan.cli.main``).

Only ``armplan demo`` and the commands that serve or record until stopped
took SIGTERM over; ``timeout 600 armplan experiment ...`` or a batch
system's SIGTERM killed the bench and the experiments outright (exit -15,
no word), their partial files left in the output folder.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest


def _catches(pid: int, signum: signal.Signals) -> bool:
    """Whether process ``pid`` has a handler of its own for ``signum`` (Linux)."""
    status = Path(f"/proc/{pid}/status").read_text()
    caught = next(line for line in status.splitlines() if line.startswith("SigCgt:"))
    return bool(int(caught.split()[1], 16) >> (signum - 1) & 1)


@pytest.mark.parametrize(
    ("signum", "code", "said"),
    [(signal.SIGTERM, 143, "terminated"), (signal.SIGHUP, 129, "hung up")],
    ids=["SIGTERM", "SIGHUP"],
)
def test_an_experiment_stopped_by_a_signal_unwinds_and_says_so(
    tmp_path: Path, signum: signal.Signals, code: int, said: str
) -> None:
    """An experiment at its full size (over a minute), signalled once its
    handlers are set: exit 128 + the signal, the signal named on stderr,
    and nothing left in its output folder (no partial file)."""
    out = tmp_path / "results"
    command = [sys.executable, "-m", "armplan", "experiment", "pace", "--out", str(out)]
    run = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        deadline = time.monotonic() + 60
        while not _catches(run.pid, signum):
            assert run.poll() is None, run.communicate()
            assert time.monotonic() < deadline, "no handler was set"
            time.sleep(0.05)
        time.sleep(0.5)  # at work
        run.send_signal(signum)
        _, stderr = run.communicate(timeout=60)
    finally:
        run.kill()
    assert run.returncode == code, stderr
    assert stderr.endswith(f"armplan: {said}\n"), stderr
    assert "Traceback" not in stderr
    assert not out.exists() or list(out.iterdir()) == []


#: The signals the CLI's handlers take over.
STOPS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def test_a_ctrl_c_as_the_handlers_are_put_back_is_said_and_leaves_them_all(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A command run in this process, and a real Ctrl-C right after its
    handler was put back as the command ended: it raised in the middle of
    putting them back, out of ``main`` (a traceback), and SIGHUP's handler
    was left raising ``HungUp`` in this process. It is the command's
    "interrupted" now, every handler the one before."""
    from armplan.cli.main import main

    before = {s: signal.getsignal(s) for s in STOPS}
    set_handler = signal.signal

    def then_ctrl_c(signum: int, handler: Any) -> Any:
        was = set_handler(signum, handler)
        if signum == signal.SIGINT and handler is before[signal.SIGINT]:
            monkeypatch.undo()
            signal.raise_signal(signal.SIGINT)  # its handler runs here
        return was

    monkeypatch.setattr(signal, "signal", then_ctrl_c)
    code: int | None = None
    try:
        code = main(["fk", "--joints", "0", "0", "0", "0.5", "0"])
    except KeyboardInterrupt:  # out of main, as it came before
        pass
    finally:
        now = {s: signal.getsignal(s) for s in STOPS}
        for signum, handler in before.items():
            set_handler(signum, handler)
    assert code == 130
    assert capsys.readouterr().err == "armplan: interrupted\n"
    assert now == before
