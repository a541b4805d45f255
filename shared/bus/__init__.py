"""The Zenoh layer every armplan process uses.

- Settings: :func:`load_config` reads the one JSON5 file (``config/zenoh.json5``)
  into a :class:`BusConfig`: router endpoints, namespace, payload limit.
- Clients: :meth:`Bus.connect` then :meth:`Bus.call` (typed reply, or the
  service's typed error raised; fast ``ServiceUnavailableError`` if it is not
  running; ``RequestTimeoutError`` when it does not answer in time).
- Services: a :class:`Route` is a key with its request and reply messages; an
  :class:`Endpoint` pairs it with an in-process function; :func:`serve` runs a
  service process, :class:`ServiceHost` serves endpoints on an open bus.
- The router: ``python -m shared.bus.router``.

Keys: ``<namespace>/<route path>`` for queries (``armplan/ik/solve``) and
``<namespace>/alive/<service>`` for liveliness tokens. See docs/services.md.
"""

from shared.bus.bus import Bus
from shared.bus.config import DEFAULT_ENDPOINT, BusConfig
from shared.bus.config_file import load_config
from shared.bus.route import Endpoint, NoArguments, Route
from shared.bus.runner import serve
from shared.bus.service import ServiceHost
from shared.bus.session import open_router

__all__ = [
    "DEFAULT_ENDPOINT",
    "Bus",
    "BusConfig",
    "Endpoint",
    "NoArguments",
    "Route",
    "ServiceHost",
    "load_config",
    "open_router",
    "serve",
]
