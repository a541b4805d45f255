"""``python -m services.timing``: run the timing service (see ``service.py``)."""

from services.timing.service import NAME, endpoints
from shared.bus import serve

if __name__ == "__main__":
    raise SystemExit(serve(NAME, endpoints))
