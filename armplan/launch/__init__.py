"""``armplan up``: start the router and every service, watch them, stop them all.

- ``bus_args.py``: the arguments that put a child on the launcher's bus.
- ``catalog.py``: which processes make up armplan and how each is started.
- ``child.py``: one child process in its own process group, stopped for sure.
- ``launcher.py``: start in order, wait for liveliness, stop in reverse order.
- ``ports.py``: a free loopback endpoint (tests, benchmarks).
- ``quoted_log.py``: a start failure quotes a temporary log's last words.
"""

from armplan.launch.catalog import SERVICES, ServiceSpec, service_spec
from armplan.launch.launcher import Launcher
from armplan.launch.ports import free_endpoint

__all__ = ["SERVICES", "Launcher", "ServiceSpec", "free_endpoint", "service_spec"]
