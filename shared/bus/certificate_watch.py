"""The running router's certificate, checked against the clock while it runs.

The start check (``certificate_dates.py``) is not enough: lab routers run for
months, and a certificate that ended meanwhile left no trace but Zenoh's
"received fatal alert: CertificateExpired" per refused client, while every
client said only "no Zenoh router answers ... or refuses this client". The
router now checks again every :data:`CHECK_EVERY` and at the end date itself:
it warns of the coming end about once a day (:data:`REPEAT_EVERY`) and, once
the end has passed, logs an ERROR naming the file and the date. It runs on:
sessions opened before may go on, new connections are refused. The dates are
those of the certificate loaded at start (Zenoh keeps it: a renewed file
needs a restart).
"""

from __future__ import annotations

import logging
import threading
import time
from datetime import UTC, datetime, timedelta
from pathlib import Path

from shared.bus.certificate_dates import (
    Validity,
    check_listen_certificate,
    date_problem,
    listen_validity,
)
from shared.bus.config import BusConfig
from shared.bus.process import POLL

#: Time between two checks of the running router's certificate [s].
CHECK_EVERY = 3600.0
#: Least time between two logs of the same problem (about a day).
REPEAT_EVERY = timedelta(days=1)
#: What an expired certificate means for the running router.
STILL_RUNNING = (
    "the router runs on: sessions opened before may go on, but it refuses "
    "every new connection"
)
#: Checked this long after the end date, so that the end has passed [s].
_PAST_END = 1.0

log = logging.getLogger("armplan.bus")


class CertificateWatch:
    """Logs what is wrong with the router's certificate, each problem once a day.

    Attributes:
        path: The certificate's file.
        validity: Its validity, read at start.
        repeat: Least time between two logs of the same problem.
    """

    def __init__(
        self, path: Path, validity: Validity, repeat: timedelta = REPEAT_EVERY
    ) -> None:
        self.path = path
        self.validity = validity
        self.repeat = repeat
        self._said: tuple[str, datetime] | None = None

    def check(self, now: datetime) -> None:
        """Log the certificate's problem at ``now`` (UTC) if it is due."""
        problem = date_problem(self.path, self.validity, now)
        if problem is None or not self._due(problem.kind, now):
            return
        self._said = (problem.kind, now)
        if problem.kind == "expired":
            log.error("router: %s; %s", problem.message, STILL_RUNNING)
        else:
            log.warning("router: %s", problem.message)

    def next_check(self, now: datetime, every: float) -> float:
        """Time from ``now`` to the next check [s]: ``every``, or to the end date."""
        left = (self.validity.end - now).total_seconds() + _PAST_END
        return min(every, left) if left > 0 else every

    def wait(self, stop: threading.Event, every: float = CHECK_EVERY) -> None:
        """Check every ``every`` seconds, and at the end date, until ``stop``."""
        due = time.monotonic() + self.next_check(datetime.now(UTC), every)
        while not stop.wait(POLL):
            if time.monotonic() >= due:
                now = datetime.now(UTC)
                self.check(now)
                due = time.monotonic() + self.next_check(now, every)

    def _due(self, kind: str, now: datetime) -> bool:
        """Whether ``kind`` is new, or last logged :attr:`repeat` ago or more."""
        if self._said is None or self._said[0] != kind:
            return True
        return now - self._said[1] >= self.repeat


def watch_certificate(config: BusConfig, now: datetime) -> CertificateWatch | None:
    """The start check of the router's certificate, and its watch for later.

    Logs a warning if it is not valid yet or ends soon.

    Returns:
        The watch, ``None`` if the router has no certificate (no TLS).

    Raises:
        BusConfigError: naming the file and its end date if it has expired or
            cannot be read as a certificate.
    """
    check_listen_certificate(config, now)
    found = listen_validity(config)
    if found is None:
        return None
    watch = CertificateWatch(*found)
    watch.check(now)
    return watch
