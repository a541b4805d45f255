"""Waiting on a libqi future, and the robot's reason from a libqi error."""

from __future__ import annotations

import re
import time
from typing import Any

#: Time between two looks at a pending libqi future [s].
POLL = 0.0005
#: Leading exception name in a libqi error text ("SimCommandError: ...").
_ERROR_NAME = re.compile(r"^\s*[A-Za-z_][\w.]*(Error|Exception): ")


def wait_future(future: Any, timeout: float) -> bool:
    """Wait at most ``timeout`` [s] for a libqi future; True if it finished.

    Polls ``isFinished`` instead of calling ``Future.wait``: in qi 3.1.5,
    ``wait`` can crash the process (double free) when the connection drops
    while it waits, which is exactly when the bridge must stay up.
    """
    deadline = time.monotonic() + timeout
    while not future.isFinished():
        if time.monotonic() >= deadline:
            return False
        time.sleep(POLL)
    return True


def robot_reason(error: BaseException | str) -> str:
    """The robot's own explanation from a libqi error (no traceback, no type)."""
    text = str(error).split("\n\nAt:", 1)[0].strip()
    return _ERROR_NAME.sub("", text, count=1) or "no reason given"
