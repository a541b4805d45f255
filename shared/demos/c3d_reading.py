"""ezc3d, run in a program of its own of bounded memory and time.

A corrupt C3D file that ``c3d_layout`` lets through can still make ezc3d
crash (a segfault ended ``armplan demos import`` of a whole batch without a
word) or allocate without bound (12.6 GB for an 8 kB file, which on a shared
machine sets the OOM killer on other services). So ezc3d reads in a child
process (``c3d_child``) whose address space may grow ``MEMORY_PER_BYTE``
times the file's size (at least ``MIN_MEMORY``) over what it starts with, and
which has ``TIMEOUT`` plus ``TIMEOUT_PER_MB`` per MB of file to answer; it
sends back the part of what ezc3d read that the import uses. A crash, a
refused allocation, an error or a timeout is a ``DemoFileError`` naming the
file.

A new program (a new interpreter, about 0.1 s), not a fork of the importer: a
fork copies every lock the importer's other threads (Zenoh's, libqi's, a
test runner's) hold at that moment, held by no one in the copy. A forked
reader of a pytest-xdist worker once answered nothing for 60 s.
"""

from __future__ import annotations

import os
import pickle
import select
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from shared.demos.c3d_child import cpu_limit
from shared.errors import DemoFileError

#: Address space the child may add per byte of the file: ezc3d and the
#: arrays it gives took 14.5 bytes per byte of a float file (29 of an
#: integer one, whose points take half the bytes).
MEMORY_PER_BYTE = 40
#: Address space the child may add in any case [bytes].
MIN_MEMORY = 512 << 20
#: The child's time to answer [s], and more per MB of file (ezc3d reads a
#: 46 MB file in 2.3 s).
TIMEOUT = 60.0
TIMEOUT_PER_MB = 1.0
#: Most characters of ezc3d's stderr quoted in an error.
MAX_SAID = 300
#: The child's program.
CHILD = Path(__file__).with_name("c3d_child.py")


def read_c3d_file(path: Path) -> dict[str, Any]:
    """What ezc3d reads of the file, as ezc3d's dict gives it, in part.

    The header's points and analogs (``size``, ``frame_rate``); the POINT and
    TRIAL parameters (each ``{"value": [...]}``); the points' positions,
    ``["data"]["points"]`` of shape (3, points, frames), NaN where a point is
    missing.

    Raises:
        DemoFileError: if ezc3d fails, crashes (the error quotes what it
            wrote to stderr), or needs more memory or time than the file's
            size allows; or if the reader cannot run (its status 1: what
            it said is quoted, and the file is not blamed).
    """
    size = path.stat().st_size
    memory = max(MIN_MEMORY, MEMORY_PER_BYTE * size)
    seconds = TIMEOUT + TIMEOUT_PER_MB * size / 1e6
    with tempfile.TemporaryFile() as errors:
        reading, writing = os.pipe()
        try:
            child = _start(path, memory, seconds, writing, errors.fileno())
        except BaseException:
            os.close(reading)
            raise
        finally:
            os.close(writing)
        answer, code, used = _wait(child, reading, seconds)
        errors.seek(0)
        said = " ".join(errors.read(MAX_SAID).decode(errors="replace").split())
    if answer and code == 0:  # a child killed as it wrote left part of one
        return _answer(path, answer, memory)
    said = f"; it said: {said}" if said else ""
    if answer is not None and code > 0:  # the reader's own failure
        raise DemoFileError(
            str(path),
            f"cannot be read: the C3D reader could not run (exit {code}){said}",
        )
    cpu, shell = cpu_limit(seconds)
    # past its CPU time limit: SIGXCPU, or the SIGKILL Linux sends instead
    # when the soft limit is the hard one (the reader's, and ``ulimit -t``'s)
    if code == -signal.SIGXCPU or (code == -signal.SIGKILL and used >= cpu):
        if shell:
            raise DemoFileError(
                str(path),
                f"cannot be read: the C3D reader took over the {cpu} s of CPU "
                "time this shell allows (ulimit -t)",
            )
        problem = f"reading it took over {cpu} s of CPU time"
    elif answer is None:
        problem = f"reading it took over {seconds:.0f} s"
    elif code < 0:
        name = signal.Signals(-code).name
        problem = f"the C3D reader (ezc3d) crashed on it ({name}), it is corrupt"
    else:
        problem = f"the C3D reader (ezc3d) ended without an answer (exit {code})"
    raise DemoFileError(str(path), f"not a readable C3D file: {problem}{said}")


def _answer(path: Path, answer: bytes, memory: int) -> dict[str, Any]:
    """The child's contents, or the error it answered."""
    kind, detail = pickle.loads(answer)
    if kind == "ok":
        return dict(detail)
    if kind == "memory":
        raise DemoFileError(
            str(path),
            f"not a readable C3D file: reading it needs over "
            f"{memory / 2**30:.1f} GiB, far more than its {path.stat().st_size} "
            "bytes hold: its sizes are corrupt",
        )
    raise DemoFileError(str(path), f"not a readable C3D file ({detail})")


def _start(
    path: Path, memory: int, seconds: float, writing: int, errors: int
) -> subprocess.Popen[bytes]:
    """The child reading ``path``, answering to ``writing``, talking to ``errors``."""
    return subprocess.Popen(
        [
            *(sys.executable, "-I", CHILD, path),
            *(str(memory), str(seconds), str(writing), str(os.getpid())),
        ],
        stdin=subprocess.DEVNULL,
        stdout=errors,
        stderr=errors,
        pass_fds=(writing,),
    )


def _wait(
    child: subprocess.Popen[bytes], reading: int, seconds: float
) -> tuple[bytes | None, int, float]:
    """The child's answer, exit code and the CPU time it used [s].

    The answer is ``None`` if it took over ``seconds`` [s]; a negative exit
    code is the signal that ended the child.
    """
    code = None
    try:
        answer = _receive(reading, seconds)
        if answer is None:
            child.kill()
        code, used = _reaped(child)
    finally:
        os.close(reading)
        if code is None:  # interrupted
            child.kill()
            child.wait()
    return answer, code, used


def _reaped(child: subprocess.Popen[bytes]) -> tuple[int, float]:
    """``child``'s exit code once it ends, and the CPU time it used [s]."""
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    return child.returncode, usage.ru_utime + usage.ru_stime


def _receive(reading: int, seconds: float) -> bytes | None:
    """All the child writes, ``None`` if it takes over ``seconds``."""
    deadline = time.monotonic() + seconds
    chunks: list[bytes] = []
    while True:
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([reading], [], [], left)[0]:
            return None
        chunk = os.read(reading, 1 << 20)
        if not chunk:
            return b"".join(chunks)
        chunks.append(chunk)
