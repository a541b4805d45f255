"""A slow network link to the robot, for the bridge tests: a TCP relay on 127.0.0.1.

A NAO is reached over a network whose bandwidth is finite (Wi-Fi: a few
MB/s at best), so a large call takes time to arrive. :class:`SlowLink`
listens on a free loopback port and relays every connection to the robot's
port, carrying the bytes toward the robot at ``bandwidth`` [B/s] and the
answers back as they come. Small messages (readings) pass at once unless a
large one is still on its way before them on the same connection, as on a
real link (each connection is carried at ``bandwidth``; readings are too
small to matter). It can also go silent, holding what it carries without
closing anything, as a link out of range does: everything
(:meth:`SlowLink.freeze`), or one connection's answers
(:meth:`SlowLink.hold_answers`, until :meth:`SlowLink.release_answers`);
or close one connection
(:meth:`SlowLink.cut`).
"""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from collections.abc import Callable

#: Bytes relayed at a time.
CHUNK = 4096
#: Time between two looks at a held link [s].
HELD_POLL = 0.005


class SlowLink:
    """A relay from a loopback port to ``127.0.0.1:robot_port``.

    Attributes:
        url: The NAOqi address to reach the robot through the link.
        bandwidth: Bytes per second carried toward the robot [B/s].
        carried: Bytes carried toward the robot so far.
        connections: Connections relayed so far, in the order they came.
    """

    def __init__(self, robot_port: int, bandwidth: float) -> None:
        self.bandwidth = bandwidth
        self.carried = 0
        self._robot_port = robot_port
        self._server = socket.create_server(("127.0.0.1", 0))
        self.url = f"tcp://127.0.0.1:{self._server.getsockname()[1]}"
        self._sockets: list[socket.socket] = []
        self.connections = 0
        self._frozen = False
        self._held: set[int] = set()
        self._closed = False
        threading.Thread(target=self._accept, name="slow-link", daemon=True).start()

    def _accept(self) -> None:
        while True:
            try:
                bridge, _ = self._server.accept()
                robot = socket.create_connection(("127.0.0.1", self._robot_port))
            except OSError:  # closed
                return
            for end in (bridge, robot):
                end.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                self._sockets.append(end)
            index = self.connections
            self.connections += 1
            threading.Thread(
                target=self._carry, args=(bridge, robot), daemon=True
            ).start()
            threading.Thread(
                target=self._answer, args=(robot, bridge, index), daemon=True
            ).start()

    def freeze(self) -> None:
        """Carry nothing more either way, on every connection, until closed."""
        self._frozen = True

    def hold_answers(self, index: int) -> None:
        """Carry no more answers back on connection ``index`` (0: the first)."""
        self._held.add(index)

    def release_answers(self, index: int) -> None:
        """Carry connection ``index``'s held answers back again, in order."""
        self._held.discard(index)

    def cut(self, index: int) -> None:
        """Close connection ``index`` (0: the first) at both ends."""
        _shut(*self._sockets[2 * index : 2 * index + 2])

    def _wait_while(self, held: Callable[[], bool]) -> None:
        while held() and not self._closed:
            time.sleep(HELD_POLL)

    def _carry(self, source: socket.socket, sink: socket.socket) -> None:
        """Toward the robot: each chunk leaves when the link has carried the last."""
        free = time.monotonic()
        try:
            while data := source.recv(CHUNK):
                free = max(free, time.monotonic()) + len(data) / self.bandwidth
                time.sleep(max(0.0, free - time.monotonic()))
                self._wait_while(lambda: self._frozen)
                sink.sendall(data)
                self.carried += len(data)
        except OSError:
            pass
        _shut(source, sink)

    def _answer(self, source: socket.socket, sink: socket.socket, index: int) -> None:
        try:
            while data := source.recv(CHUNK):
                self._wait_while(lambda: self._frozen or index in self._held)
                sink.sendall(data)
        except OSError:
            pass
        _shut(source, sink)

    def close(self) -> None:
        """Stop listening and cut every connection."""
        self._closed = True
        _shut(self._server)  # wakes the accepting thread
        self._server.close()
        for end in self._sockets:
            _shut(end)
            end.close()


def _shut(*ends: socket.socket) -> None:
    for end in ends:
        with contextlib.suppress(OSError):
            end.shutdown(socket.SHUT_RDWR)
