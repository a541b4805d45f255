"""ezc3d, run in a child process of bounded memory and time.

A corrupt C3D file that ``c3d_layout`` lets through can still make ezc3d
crash (a segfault ended ``armplan demos import`` of a whole batch without a
word) or allocate without bound (12.6 GB for an 8 kB file, which on a shared
machine sets the OOM killer on other services). So ezc3d reads in a forked
child whose address space may grow ``MEMORY_PER_BYTE`` times the file's size
(at least ``MIN_MEMORY``) over what it starts with, and which has
``TIMEOUT`` plus ``TIMEOUT_PER_MB`` per MB of file to answer; it sends back
the part of what ezc3d read that the import uses. A crash, a refused
allocation, an error or a timeout is a ``DemoFileError`` naming the file.

Forked, not started anew: the child has ezc3d and numpy loaded already, and
costs 10 to 25 ms where a new interpreter importing ezc3d takes 250 ms. The
import runs one thread, which makes the fork safe.
"""

from __future__ import annotations

import contextlib
import faulthandler
import math
import os
import pickle
import resource
import select
import signal
import tempfile
import time
from pathlib import Path
from typing import Any, NoReturn

import ezc3d
import numpy as np

from shared.errors import DemoFileError
from shared.parent_death import die_with_parent

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
#: Parameter groups the import uses.
GROUPS = ("POINT", "TRIAL")


def read_c3d_file(path: Path) -> dict[str, Any]:
    """What ezc3d reads of the file, as ezc3d's dict gives it, in part.

    The header's points and analogs (``size``, ``frame_rate``); the POINT and
    TRIAL parameters (each ``{"value": [...]}``); the points' positions,
    ``["data"]["points"]`` of shape (3, points, frames), NaN where a point is
    missing.

    Raises:
        DemoFileError: if ezc3d fails, crashes (the error quotes what it
            wrote to stderr), or needs more memory or time than the file's
            size allows.
    """
    size = path.stat().st_size
    memory = max(MIN_MEMORY, MEMORY_PER_BYTE * size)
    seconds = TIMEOUT + TIMEOUT_PER_MB * size / 1e6
    with tempfile.TemporaryFile() as errors:
        reading, writing = os.pipe()
        pid = os.fork()
        if pid == 0:
            os.close(reading)
            _child(path, memory, seconds, writing, errors.fileno())
        os.close(writing)
        answer, status = _wait(pid, reading, seconds)
        errors.seek(0)
        said = " ".join(errors.read(MAX_SAID).decode(errors="replace").split())
    if answer:
        return _answer(path, answer, memory)
    if answer is None:
        problem = f"reading it took over {seconds:.0f} s"
    elif os.WIFSIGNALED(status):
        name = signal.Signals(os.WTERMSIG(status)).name
        problem = f"the C3D reader (ezc3d) crashed on it ({name}), it is corrupt"
    else:
        code = os.waitstatus_to_exitcode(status)
        problem = f"the C3D reader (ezc3d) ended without an answer (exit {code})"
    said = f"; it said: {said}" if said else ""
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


def _wait(pid: int, reading: int, seconds: float) -> tuple[bytes | None, int]:
    """The child's answer (``None`` if it took over ``seconds``) and status."""
    status = None
    try:
        answer = _receive(reading, seconds)
        if answer is None:
            os.kill(pid, signal.SIGKILL)
        status = os.waitpid(pid, 0)[1]
    finally:
        os.close(reading)
        if status is None:  # interrupted
            _stop(pid)
    return answer, status


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


def _stop(pid: int) -> None:
    """End the child (it took too long, or the parent was interrupted)."""
    with contextlib.suppress(ProcessLookupError):
        os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)


def _child(
    path: Path, memory: int, seconds: float, writing: int, errors: int
) -> NoReturn:
    """Read the file, write the outcome to ``writing``, exit; never returns.

    ``errors`` gets what ezc3d writes to stderr (as it aborts, say); a
    crash is left to the parent to name (no Python traceback of it).
    """
    try:
        faulthandler.disable()
        os.dup2(errors, 2)
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        _end_with_parent(seconds)
        _limit_memory(memory)
        try:
            answer = pickle.dumps(("ok", _contents(ezc3d.c3d(str(path)))))
        except MemoryError:
            answer = pickle.dumps(("memory", ""))
        except Exception as exc:  # anything ezc3d raises is the file's fault
            kind = "memory" if "bad_alloc" in str(exc) else "error"
            answer = pickle.dumps((kind, str(exc)))
        with os.fdopen(writing, "wb") as out:
            out.write(answer)
    finally:
        os._exit(0)


def _end_with_parent(seconds: float) -> None:
    """End this child with its parent, and after ``seconds`` of CPU [s].

    A parent killed alone (``kill PID``) left the child reading, its time
    limit gone with the parent that kept it: now the kernel sends SIGKILL
    when the parent exits, and CPU time past the limit ends it anyway.
    """
    parent = os.getppid()
    die_with_parent(signal.SIGKILL)
    if os.getppid() != parent:  # the parent died before the request took
        os._exit(1)
    cpu = math.ceil(seconds)
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu))


def _limit_memory(memory: int) -> None:
    """Let the address space grow by ``memory`` bytes at most."""
    try:
        with open("/proc/self/statm") as statm:
            used = int(statm.read().split()[0]) * resource.getpagesize()
    except OSError:  # not Linux: no /proc
        return
    _, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = used + memory
    if hard != resource.RLIM_INFINITY:
        limit = min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))


def _contents(data: Any) -> dict[str, Any]:
    """The part of ezc3d's reading the import uses, in plain types."""
    header = data["header"]
    parameters = data["parameters"]
    return {
        "header": {
            part: {key: header[part][key] for key in ("size", "frame_rate")}
            for part in ("points", "analogs")
        },
        "parameters": {
            group: {
                name: {"value": np.asarray(parameter["value"]).tolist()}
                for name, parameter in parameters[group].items()
                if name != "__METADATA__"
            }
            for group in GROUPS
            if group in parameters
        },
        "data": {"points": np.array(data["data"]["points"][:3], dtype=float)},
    }
