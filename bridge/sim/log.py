"""The simulated NAO's log: what it received and what it did, as JSON lines.

Each line is one JSON object with ``t`` (seconds since the sim started, its
monotonic clock) and ``event``:

- ``start``: ``url``, ``period`` [s], ``joints`` (name -> [lower, upper,
  velocity]), ``origin`` (the monotonic clock at ``t = 0`` [s], to line the
  log up with other processes on the same machine).
- ``call``: a command received (``t``: when it took effect, the time its
  key times count from; an ``angleInterpolation``'s once its keys were read,
  which for 44 000 keys took 0.1 s; a refused command's when it came):
  ``method`` and its arguments (``names``, ``angles``/``stiffness``,
  ``times``, ...). Reads (``getAngles``, ``getStiffnesses``, ...) are not
  logged. The line is written once the command is applied (a call of
  44 000 keys takes 0.3 s to write), so the first ``state`` lines of a long
  call's movement can come before it.
- ``refused``: ``method`` and ``reason``; nothing of the command executed.
- ``motion``: an accepted command: ``method``, ``joints``, ``duration`` [s].
- ``done`` / ``interrupted``: ``method``, ``joints`` (and ``reason``); a
  ``done``'s ``t`` is the cycle that found the command finished.
- ``state``: each control cycle while a command runs: ``cycle`` and
  ``positions`` (joint -> measured angle [rad]) of the moving joints; its
  ``t`` is the time the cycle committed those positions, so a line written
  late still gives the motor's true speed. A kill (``killTasksUsingResources``,
  ``killAll``, ``rest``) logs one more, at its own time, of the joints it
  stopped while commanded, with ``stopped`` (the reason); the next cycle
  logs them once more, where they hold, and then no more.
- ``stop``: the sim is shutting down.

If the file cannot be written (a full disk), the sim stops writing it with
one warning on stderr naming it; its ALMotion calls go on.

The log keeps no entry in memory unless asked to (``keep``): the sim's
process never reads its own log back, and it kept the last 20 000 entries
(13 MB of one arm's ``state`` lines) whether ``--log`` was given or not. Code
that runs the sim in-process (the tests) asks for the entries it reads
with :meth:`SimLog.entries`.
"""

from __future__ import annotations

import contextlib
import json
import sys
import threading
import time
from collections import deque
from pathlib import Path
from typing import Any, TextIO

from shared.errors import InvalidInputError

#: Entries an in-process reader keeps by asking for them (``SimLog(keep=KEEP)``).
KEEP = 20000


def open_log(path: str | Path) -> TextIO:
    """The log file ``path`` opened to append; InvalidInputError if it cannot be.

    Raises:
        InvalidInputError: naming the path and the reason (empty path, a
            folder, a missing folder, no permission).
    """
    if not str(path):
        raise InvalidInputError("the sim log's path is empty", field="log")
    try:
        return open(path, "a", encoding="utf-8")
    except OSError as exc:
        raise InvalidInputError(
            f"cannot write the sim log {path}: {exc.strerror}", field="log"
        ) from None


def check_log_file(path: str | Path) -> Path:
    """``path`` if the sim can append its log there (made if missing).

    Raises:
        InvalidInputError: as :func:`open_log`.
    """
    open_log(path).close()
    return Path(path)


class SimLog:
    """A thread-safe JSON-lines log, flushed at every line; the last few in memory."""

    def __init__(self, path: str | Path | None = None, keep: int = 0) -> None:
        """Start the log.

        Args:
            path: Append it to this file (None: no file).
            keep: Keep the last ``keep`` entries in memory, for
                :meth:`entries` (0: none, as the sim's process does).

        Raises:
            InvalidInputError: if the file cannot be opened to append.
        """
        self._origin = time.monotonic()
        self._lock = threading.Lock()
        self._entries: deque[dict[str, Any]] = deque(maxlen=keep)
        self._file = None if path is None else open_log(path)

    @property
    def origin(self) -> float:
        """The monotonic clock when the log started [s]."""
        return self._origin

    def since_start(self, t: float) -> float:
        """Monotonic time ``t`` as seconds since the log started [s]."""
        return t - self._origin

    def write(self, event: str, at: float | None = None, **fields: Any) -> None:
        """Append one entry ``{"t", "event", **fields}``.

        Args:
            event: The entry's kind.
            at: The monotonic time the entry describes [s] (default: now).
            fields: The entry's other fields.
        """
        stamp = time.monotonic() if at is None else at
        entry = {"t": round(self.since_start(stamp), 6), "event": event}
        entry.update(fields)
        line = json.dumps(entry)
        with self._lock:
            self._entries.append(entry)
            if self._file is not None:
                self._append(line)

    def _append(self, line: str) -> None:
        """Append ``line`` to the file; on a write error, stop writing it.

        A full disk (or a file size limit) must not fail the ALMotion call
        being logged (the bridge took it for a killed motion): the sim says
        so once on stderr, naming the file; later entries are kept only in
        memory, if it keeps any.
        """
        assert self._file is not None
        try:
            self._file.write(line + "\n")
            self._file.flush()
        except OSError as error:
            name = self._file.name
            with contextlib.suppress(OSError):  # its buffer cannot be written
                self._file.close()
            self._file = None
            sys.stderr.write(
                f"sim: warning: stopped writing the sim log {name}: "
                f"{error.strerror}; later entries are not written\n"
            )
            sys.stderr.flush()

    def entries(self) -> list[dict[str, Any]]:
        """A copy of the entries kept in memory: the last ``keep`` written."""
        with self._lock:
            return list(self._entries)

    def close(self) -> None:
        """Close the file."""
        with self._lock:
            if self._file is not None:
                with contextlib.suppress(OSError):  # said at the failed write
                    self._file.close()
                self._file = None


def read_log(path: str | Path) -> list[dict[str, Any]]:
    """The entries of a sim log file (a torn last line is skipped)."""
    entries = []
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        try:
            entries.append(json.loads(line))
        except json.JSONDecodeError:
            continue
    return entries
