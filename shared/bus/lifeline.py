"""End a child process when the launcher that started it dies.

``armplan up`` sets ``ARMPLAN_PARENT_PID`` for each child. The child then
asks Linux to send it SIGTERM when its parent dies (``PR_SET_PDEATHSIG``),
and, on any system, a watchdog thread checks every ``CHECK_EVERY`` seconds
that the parent is still its parent. Either way the child's own SIGTERM
handler shuts it down cleanly, so even a launcher killed with SIGKILL leaves
no process behind.
"""

from __future__ import annotations

import os
import signal
import threading
import time

from shared.parent_death import die_with_parent

#: Environment variable holding the launcher's PID.
PARENT_ENV = "ARMPLAN_PARENT_PID"
#: Period of the watchdog's check [s].
CHECK_EVERY = 0.5


def watch_parent() -> bool:
    """Arrange SIGTERM to this process when the launcher dies.

    Returns:
        ``True`` if a launcher is watched (``ARMPLAN_PARENT_PID`` set).
    """
    raw = os.environ.get(PARENT_ENV, "")
    if not raw.isdigit():
        return False
    parent = int(raw)
    die_with_parent()
    thread = threading.Thread(
        target=_watch, args=(parent,), name="parent-watchdog", daemon=True
    )
    thread.start()
    return True


def _watch(parent: int) -> None:
    """Send SIGTERM to this process once ``parent`` is no longer its parent."""
    while os.getppid() == parent:
        time.sleep(CHECK_EVERY)
    os.kill(os.getpid(), signal.SIGTERM)
