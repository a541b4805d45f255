"""ezc3d's reading of one C3D file, as a program of its own (``c3d_reading``).

Run as ``python -I c3d_child.py FILE MEMORY SECONDS FD PARENT``: reads FILE
with ezc3d, its address space grown by MEMORY bytes at most and its CPU time
SECONDS at most (less if a hard limit says so), and writes a pickled
``(kind, detail)`` to file descriptor FD: ``("ok", contents)``,
``("memory", "")`` or ``("error", message)``. It ends when PARENT (a process
id) does. A crash leaves no answer, for the parent to name; a failure of its
own (not ezc3d's) is one line on stderr and exit status 1.

A script, not a module of the package: importing ``shared`` would load libqi
and pinocchio for nothing (a new interpreter with numpy and ezc3d alone
starts in about 0.1 s).
"""

from __future__ import annotations

import ctypes
import math
import os
import pickle
import resource
import signal
import sys
from typing import Any, NoReturn

import ezc3d
import numpy as np

#: Parameter groups the import uses.
GROUPS = ("POINT", "TRIAL")
#: Linux's ``prctl`` option: a signal when the parent ends.
PR_SET_PDEATHSIG = 1


def main(argv: list[str]) -> NoReturn:
    """Read the file, write the outcome to the descriptor, exit; never returns.

    What ezc3d writes (to stderr as it aborts, say) goes where this
    program's stderr does, and so does this program's own failure (setting
    its limits, say), which ends it with status 1: it used to end with 0 and
    no word, blamed on the file.
    """
    status = 0
    try:
        path, memory, seconds, writing, parent = argv
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        _end_with_parent(int(parent), float(seconds))
        _limit_memory(int(memory))
        try:
            answer = pickle.dumps(("ok", _contents(ezc3d.c3d(path))))
        except MemoryError:
            answer = pickle.dumps(("memory", ""))
        except Exception as exc:  # anything ezc3d raises is the file's fault
            kind = "memory" if "bad_alloc" in str(exc) else "error"
            answer = pickle.dumps((kind, str(exc)))
        with os.fdopen(int(writing), "wb") as out:
            out.write(answer)
    except BaseException as exc:  # this program's failure, not the file's
        print(f"{type(exc).__name__}: {exc}", file=sys.stderr, flush=True)
        status = 1
    finally:
        os._exit(status)


def _end_with_parent(parent: int, seconds: float) -> None:
    """End this program with ``parent``, and after ``seconds`` of CPU [s].

    A parent killed alone (``kill PID``) would leave the reader reading, its
    time limit gone with the parent that kept it: on Linux the kernel sends
    SIGKILL when the parent ends, and CPU time past the limit ends it anyway.
    A hard limit already set (``ulimit -t 50`` in the shell) is kept, not
    raised: raising it failed, and every C3D file, however good, was "not
    a readable C3D file: the C3D reader (ezc3d) ended without an answer".
    """
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent:  # the parent ended before the request took
        os._exit(1)
    cpu, _ = cpu_limit(seconds)
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu))


def cpu_limit(seconds: float) -> tuple[int, bool]:
    """The reader's CPU time limit [s], and whether the shell set it.

    ``seconds`` [s] rounded up, unless a hard limit already set is lower (a
    shell's ``ulimit -t``): that one is kept, not raised. The importer reads
    a reader's end by the same limit (``c3d_reading``).
    """
    cpu = math.ceil(seconds)
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    if hard != resource.RLIM_INFINITY and hard < cpu:
        return hard, True
    return cpu, False


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


if __name__ == "__main__":
    main(sys.argv[1:])
