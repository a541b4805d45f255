"""Which callers' sessions have ended: their caller tokens, watched.

Every :class:`~shared.bus.Bus` holds the liveliness token
``<ns>/caller/<its session id>`` while it is open, and every query it sends
names that id (``CallerBudget.session``). Zenoh removes the token when the
session ends, however it ends: closed on Ctrl-C, or its connection dropped
when the process was killed. A service that must not do something for a
caller who is no longer there (the planner publishing a plan, which a
following bridge plays) watches the tokens go with a :class:`GoneCallers`.

Only a removal seen counts: a caller whose token was never seen (an older
client, a raw Zenoh query, a router that refuses the token) is never taken
for gone.
"""

from __future__ import annotations

import threading
from collections import OrderedDict

import zenoh

from shared.bus.keys import CALLER, caller_pattern

#: Most ended sessions remembered; the oldest are forgotten first.
REMEMBERED = 4096


class GoneCallers:
    """The sessions whose caller token was removed, seen from one session."""

    def __init__(self, session: zenoh.Session, namespace: str) -> None:
        self._prefix = f"{namespace}/{CALLER}/"
        self._gone: OrderedDict[str, None] = OrderedDict()
        self._lock = threading.Lock()
        self._subscriber = session.liveliness().declare_subscriber(
            caller_pattern(namespace), self._on_sample
        )

    def _on_sample(self, sample: zenoh.Sample) -> None:
        caller = str(sample.key_expr).removeprefix(self._prefix)
        with self._lock:
            if sample.kind == zenoh.SampleKind.PUT:  # (again: reconnected)
                self._gone.pop(caller, None)
                return
            self._gone[caller] = None
            self._gone.move_to_end(caller)
            while len(self._gone) > REMEMBERED:
                self._gone.popitem(last=False)

    def gone(self, caller: str | None) -> bool:
        """Whether the session ``caller`` (its id; None: not said) has ended."""
        if caller is None:
            return False
        with self._lock:
            return caller in self._gone

    def close(self) -> None:
        """Stop watching (before the session closes)."""
        self._subscriber.undeclare()  # type: ignore[no-untyped-call]
