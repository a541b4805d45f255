"""``python -m services.planner``: run the planner service (see ``service.py``)."""

from services.planner.service import NAME, endpoints
from shared.bus import serve

if __name__ == "__main__":
    raise SystemExit(serve(NAME, endpoints))
