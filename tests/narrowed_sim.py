"""A simulated NAO whose robot description differs from the bridge's in one joint."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager

from bridge.sim.process import READY

NARROWED_SIM = """
import sys
import shared
from bridge.sim.joints import joint_specs
specs = joint_specs()
joint, quantity, by = sys.argv[1], sys.argv[2], float(sys.argv[3])
value = getattr(specs[joint], quantity) - by
specs[joint] = specs[joint]._replace(**{quantity: value})
from bridge.sim.server import serve
serve("tcp://127.0.0.1:0")
"""


@contextmanager
def narrowed_sim(joint: str, quantity: str, by: float) -> Iterator[str]:
    """A simulated NAO whose ``joint``'s ``quantity`` (upper [rad], velocity
    [rad/s]) is ``by`` less than the robot description's; its address."""
    process = subprocess.Popen(
        [sys.executable, "-c", NARROWED_SIM, joint, quantity, repr(float(by))],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        assert process.stdout is not None
        line = next(out for out in process.stdout if out.startswith(READY))
        yield line.split()[-1]
    finally:
        process.terminate()
        process.wait(10)
