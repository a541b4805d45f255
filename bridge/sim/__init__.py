"""The simulated NAO: ALMotion served over libqi, run as its own process.

Start it with ``python -m bridge.sim --listen tcp://127.0.0.1:9559`` (or
``armplan sim``); the bridge reaches it exactly as it reaches a real NAO.
It lives under ``bridge/`` because it is the bridge's counterpart and ships
in the same wheel; it imports nothing from the bridge but ``process.py``'s
launcher is what the bridge's tests and the demo use to start it.
"""

from bridge.sim.process import READY, SimProcess

__all__ = ["READY", "SimProcess"]
