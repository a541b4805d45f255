"""A slow network link to the robot, for the bridge tests: a TCP relay on 127.0.0.1.

A NAO is reached over a network whose bandwidth is finite (Wi-Fi: a few
MB/s at best), so a large call takes time to arrive. :class:`SlowLink`
listens on a free loopback port and relays every connection to the robot's
port, carrying the bytes toward the robot at ``bandwidth`` [B/s] and the
answers back as they come. Small messages (readings) pass at once unless a
large one is still on its way before them, as on a real link.
"""

from __future__ import annotations

import contextlib
import socket
import threading
import time

#: Bytes relayed at a time.
CHUNK = 4096


class SlowLink:
    """A relay from a loopback port to ``127.0.0.1:robot_port``.

    Attributes:
        url: The NAOqi address to reach the robot through the link.
        bandwidth: Bytes per second carried toward the robot [B/s].
        carried: Bytes carried toward the robot so far.
    """

    def __init__(self, robot_port: int, bandwidth: float) -> None:
        self.bandwidth = bandwidth
        self.carried = 0
        self._robot_port = robot_port
        self._server = socket.create_server(("127.0.0.1", 0))
        self.url = f"tcp://127.0.0.1:{self._server.getsockname()[1]}"
        self._sockets: list[socket.socket] = []
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
            threading.Thread(
                target=self._carry, args=(bridge, robot), daemon=True
            ).start()
            threading.Thread(
                target=self._answer, args=(robot, bridge), daemon=True
            ).start()

    def _carry(self, source: socket.socket, sink: socket.socket) -> None:
        """Toward the robot: each chunk leaves when the link has carried the last."""
        free = time.monotonic()
        try:
            while data := source.recv(CHUNK):
                free = max(free, time.monotonic()) + len(data) / self.bandwidth
                time.sleep(max(0.0, free - time.monotonic()))
                sink.sendall(data)
                self.carried += len(data)
        except OSError:
            pass
        _shut(source, sink)

    def _answer(self, source: socket.socket, sink: socket.socket) -> None:
        try:
            while data := source.recv(CHUNK):
                sink.sendall(data)
        except OSError:
            pass
        _shut(source, sink)

    def close(self) -> None:
        """Stop listening and cut every connection."""
        _shut(self._server)  # wakes the accepting thread
        self._server.close()
        for end in self._sockets:
            _shut(end)
            end.close()


def _shut(*ends: socket.socket) -> None:
    for end in ends:
        with contextlib.suppress(OSError):
            end.shutdown(socket.SHUT_RDWR)
