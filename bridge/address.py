"""Where the robot is: the NAOqi address the bridge connects to.

The address is the ``--robot`` option, else the environment variable
``ARMPLAN_ROBOT``, else the simulated NAO on 127.0.0.1 (``armplan sim``): a
real NAO is used only when the user names it (``tcp://IP:9559``).
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping

from shared.errors import InvalidInputError
from shared.every_interface import names_every_interface

#: Environment variable naming the robot's NAOqi address.
ROBOT_ENV = "ARMPLAN_ROBOT"
#: The simulated NAO's default address (``armplan sim``).
DEFAULT_ROBOT = "tcp://127.0.0.1:9559"
_URL = re.compile(r"^tcps?://[A-Za-z0-9_.\-]+:([0-9]{1,5})$")  # ASCII digits only


def check_robot_url(url: str) -> str:
    """``url`` if it is a NAOqi address ``tcp://HOST:PORT``; else InvalidInputError."""
    match = _URL.fullmatch(url)  # no trailing newline
    if match is None or not 0 < int(match.group(1)) < 65536:
        raise InvalidInputError(
            f"robot address {url!r} must look like tcp://HOST:PORT "
            "(a real NAO: tcp://IP:9559)",
            field="robot",
        )
    return url


def check_listen_url(url: str) -> str:
    """``url`` if it is an address to serve at; else InvalidInputError.

    The address reads ``tcp://HOST:PORT``; port 0 means any free one. The
    host is one interface's address or a name, never the unspecified
    (all-zero) address of IPv4 or IPv6: a simulated NAO listening there
    would take commands from every network the machine is on.
    """
    if names_every_interface(_host(url)):
        raise InvalidInputError(
            f"listen address {url!r} names every interface: give the address "
            "of the one the bridge reaches (127.0.0.1 on one machine)",
            field="listen",
        )
    match = _URL.fullmatch(url)  # no trailing newline
    if match is None or not 0 <= int(match.group(1)) < 65536:
        raise InvalidInputError(
            f"listen address {url!r} must look like tcp://HOST:PORT with a port "
            "0..65535 (0: any free port)",
            field="listen",
        )
    return url


def _host(url: str) -> str:
    """The ``HOST`` of ``SCHEME://HOST:PORT`` as written (brackets kept)."""
    return url.partition("://")[2].rpartition(":")[0]


def robot_url(given: str | None, environ: Mapping[str, str] = os.environ) -> str:
    """The robot's address: ``given``, else ``$ARMPLAN_ROBOT``, else the sim's."""
    return check_robot_url(given or environ.get(ROBOT_ENV) or DEFAULT_ROBOT)
