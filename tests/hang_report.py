"""What a process tree that outlived a test's wait was doing, for its failure.

A test that waits for a process to exit and runs out of time reports, before
it kills anything: each process still alive at or below the one it waited
for, with its command line; the threads of each Python one, read from
outside by ``py-spy dump --native`` (nothing is stopped or changed: Python
frames and the native ones beneath, Zenoh's Rust among them); and the tails
of the log files the test names. A hang seen once in CI (a demo that did
not exit within 90 s of SIGTERM) left only "timed out" to go on.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from collections.abc import Iterable
from pathlib import Path

#: Longest wait for one ``py-spy dump`` [s].
DUMP_TIMEOUT = 30.0
#: Characters kept from the end of each log file and of each dump.
TAIL = 4000


def hang_report(root: int, logs: Iterable[Path] = (), stderr: str = "") -> str:
    """A report on process ``root`` and everything alive below it.

    Args:
        root: The PID waited for (still running).
        logs: Files whose tails to add (e.g. the demo's ``logs/*.log``).
        stderr: What ``root`` wrote on stderr so far (left out if empty).
    """
    parts = [f"--- stderr of {root} (tail) ---\n{stderr[-TAIL:]}"] if stderr else []
    for pid in [root, *sorted(_below(root))]:
        command = _command(pid)
        if command is None:
            continue
        parts.append(f"--- process {pid}: {command[:300]}")
        if "python" in command:
            parts.append(_dump(pid)[-TAIL:])
    for path in sorted(logs):
        try:
            text = path.read_text(errors="replace")
        except OSError as error:
            text = f"(unreadable: {error})"
        parts.append(f"--- {path} (tail) ---\n{text[-TAIL:]}")
    return "\n".join(parts)


def _below(root: int) -> set[int]:
    """The PIDs of every process below ``root`` (children, theirs, ...)."""
    parents: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        parent = int(stat[stat.rindex(")") + 2 :].split()[1])
        parents.setdefault(parent, []).append(int(entry.name))
    found: set[int] = set()
    todo = [root]
    while todo:
        for child in parents.get(todo.pop(), []):
            found.add(child)
            todo.append(child)
    return found


def _command(pid: int) -> str | None:
    """The command line of ``pid``, or None if it is gone."""
    try:
        raw = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return None
    return raw.replace(b"\0", b" ").decode(errors="replace").strip() or None


def _dump(pid: int) -> str:
    """``py-spy dump --native`` of ``pid``, or why there is none."""
    spy = shutil.which("py-spy") or str(Path(sys.executable).parent / "py-spy")
    try:
        done = subprocess.run(
            [spy, "dump", "--native", "--pid", str(pid)],
            capture_output=True,
            text=True,
            timeout=DUMP_TIMEOUT,
            check=False,
        )
    except (OSError, subprocess.TimeoutExpired) as error:
        return f"(no py-spy dump: {error})"
    return done.stdout + done.stderr
