"""One process per service and namespace (``shared/bus/service_alone.py``).

Real router and service processes on a free loopback port.
"""

from __future__ import annotations

import subprocess
import sys

from armplan.launch import Launcher, free_endpoint
from shared.bus import Bus, load_config

#: Longest wait for a service process to give up [s].
EXIT_TIMEOUT = 60.0


def test_a_second_service_in_the_namespace_refuses_to_start() -> None:
    """A second ``python -m services.timing`` on the router of ``armplan up``
    (or on a router linked to it) served beside the first: two planners
    published one ``armplan plan`` three times for a following robot. It
    now exits 1 naming the held token, and the first serves on."""
    config = load_config(None, (free_endpoint(),))
    with Launcher(config, ["timing"]) as stack:
        command = [sys.executable, "-m", "services.timing", "--wait", "10"]
        second = subprocess.run(
            [*command, "--connect", config.endpoints[0]],
            capture_output=True,
            text=True,
            timeout=EXIT_TIMEOUT,
            check=False,
        )
        assert second.returncode == 1, second.stderr
        assert (
            "service timing: service 'timing' is already running "
            "(armplan/alive/timing is held by another process): two timing "
            "services in one namespace would each answer every request"
        ) in second.stderr
        assert stack.exited() == []
        with Bus.connect(config) as bus:
            assert "timing" in bus.alive()
