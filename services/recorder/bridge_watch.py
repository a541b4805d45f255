"""Watch for a bridge coming alive while a replay of every key runs.

A replay without ``--keys`` is refused when a bridge is alive in its
namespace (``armplan replay``), but that check is made once, before the
first message: a bridge started during a long replay received the rest of
the recorded trajectories and, with ``--follow``, played them on the arm.
:class:`BridgeWatch` declares a liveliness subscriber on the bridge's token
(``<ns>/alive/bridge``) before that check, so a bridge appearing between the
check and the first message is seen too, and flags the first appearance.
The replay checks the flag immediately before each put; a put already made
when the token arrives cannot be recalled.

Declared without ``history`` (see ``shared.bus.liveness``): with it, the
liveliness query of the check made just after returned no tokens.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

import zenoh

from shared.bus.keys import alive_key
from shared.lifecycle import Closes

#: The service whose liveliness token is watched.
BRIDGE = "bridge"


class BridgeWatch(Closes):
    """Whether a bridge's token has appeared since this was built.

    Args:
        session: The replay's open session (close this first).
        namespace: The replay's namespace.
        on_appear: Called once, on Zenoh's thread, when the token first
            appears, e.g. to wake the replay's wait (it must not block).

    Attributes:
        appeared: Set on the token's first appearance; never cleared (a
            bridge that came and went may come back).
    """

    def __init__(
        self,
        session: zenoh.Session,
        namespace: str,
        on_appear: Callable[[], None] = lambda: None,
    ) -> None:
        self.appeared = threading.Event()
        self._on_appear = on_appear
        self._lock = threading.Lock()
        self._subscriber = session.liveliness().declare_subscriber(
            alive_key(namespace, BRIDGE), self._on_sample
        )

    def _on_sample(self, sample: zenoh.Sample) -> None:
        if sample.kind != zenoh.SampleKind.PUT:
            return
        with self._lock:
            first = not self.appeared.is_set()
            self.appeared.set()
        if first:
            self._on_appear()

    def close(self) -> None:
        """Stop watching (before the session closes)."""
        self._subscriber.undeclare()  # type: ignore[no-untyped-call]
