"""Printing results and errors."""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from armplan.cli.stdout_guard import discard_stdout
from shared.errors import ArmplanError
from shared.output_paths import is_standard_output
from shared.printable import printable_lines


def say(line: str) -> None:
    """Print one progress line; once nobody reads stdout, print no more.

    Nobody reads it once its reader has gone (``| head -1``: a broken pipe)
    or its terminal has closed (a write fails with EIO after the hangup).
    The command goes on: it still stops its processes and closes its files
    (a failed write used to end it there, with a traceback and exit code 1).
    """
    try:
        sys.stdout.write(line + "\n")
        sys.stdout.flush()
    except OSError:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # the rest (and exit's flush) lost
        os.close(devnull)


@contextlib.contextmanager
def apart_from(output: str | Path) -> Iterator[None]:
    """Print on stderr, in the block, if ``output`` is where stdout goes.

    ``-o /dev/stdout > file`` (or ``| next``): a command's own lines (its
    summary, its tables) went into the file it wrote, over its first bytes
    or after them (an MCAP's header overwritten by "/dev/stdout: 1 subject
    ..."). Checked on entry, before the file is written or replaced.
    With stderr there too (``-o /dev/stdout > play.py 2>&1``) the lines
    are dropped: on stderr they overwrote the script's first line.
    """
    if not is_standard_output(output):
        yield
        return
    both = is_standard_output(output, fd=2)
    with contextlib.redirect_stdout(io.StringIO() if both else sys.stderr):
        yield


def print_json(data: Any) -> None:
    """Print ``data`` as strict JSON on stdout (NaN and infinities as null)."""
    sys.stdout.write(json.dumps(_finite(data), indent=2, allow_nan=False) + "\n")


def _finite(data: Any) -> Any:
    """``data`` with every non-finite float replaced by ``None``."""
    if isinstance(data, float):
        return data if math.isfinite(data) else None
    if isinstance(data, dict):
        return {key: _finite(value) for key, value in data.items()}
    if isinstance(data, list | tuple):
        return [_finite(value) for value in data]
    return data


def print_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> None:
    """Print a plain aligned table on stdout."""
    cells = [[str(h) for h in headers]] + [[_cell(v) for v in row] for row in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(headers))]
    for row in cells:
        first = row[0].ljust(widths[0])
        rest = (c.rjust(w) for c, w in zip(row[1:], widths[1:], strict=True))
        sys.stdout.write("  ".join((first, *rest)) + "\n")


def angle_text(value: float, low: float, high: float) -> str:
    """A joint angle [rad] to 5 decimals, or to more where 5 would leave its range.

    A posture on a limit, say RShoulderRoll at 0.314159 rad, prints as
    0.31416 to 5 decimals: outside [low, high] [rad], so fed back to
    ``fk --joints`` or ``--start`` it was refused. Such a value gets the
    fewest more decimals that stay within the range (here 0.314159), and
    every printed value is still the true one, correctly rounded.
    """
    for digits in range(5, 18):
        text = f"{value:.{digits}f}"
        if low <= float(text) <= high:
            return text
    return repr(value)  # outside the range itself: exactly, as it is


def _cell(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.5f}"
    return str(value)


#: A service's words for a request's fields, as the CLI's options say them:
#: services word their errors by JSON field (a client of the bus has no
#: options); the CLI tells its user the option to change.
OPTION_WORDS = {
    "raise limits.jerk / limits.acceleration": "raise --max-jerk / --max-acceleration",
    "swivel is the goal of": "--swivel is the goal of",
    "(give primitive '": "(give --primitive '",
    "primitive applies to method": "--primitive applies to method",
}


def in_option_terms(message: str) -> str:
    """``message`` with the JSON fields it names as the CLI's options."""
    for field, option in OPTION_WORDS.items():
        message = message.replace(field, option)
    return message


def report_error(error: ArmplanError, as_json: bool) -> int:
    """Tell the user what went wrong; returns the exit code (1).

    On stderr, and with ``as_json`` on stdout too, as far as each can be
    written (closed, ``None``, or a full disk: the exit code still says it).
    A message may quote names from a file or the network (a recorded
    topic): on stderr its control characters are escaped
    (:func:`~shared.printable.printable_lines`), so none reaches the
    terminal; JSON escapes them itself. A service's words for a field are
    told as the option that sets it (:func:`in_option_terms`).
    """
    message = in_option_terms(error.message)
    with contextlib.suppress(OSError, AttributeError):
        sys.stderr.write(f"armplan: error: {printable_lines(message)}\n")
        sys.stderr.flush()
    if as_json:
        try:
            print_json({"error": error.to_wire() | {"message": message}})
            sys.stdout.flush()
        except (OSError, AttributeError):
            if sys.stdout is sys.__stdout__:  # exit's flush would fail again
                discard_stdout()
    return 1
