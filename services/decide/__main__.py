"""``python -m services.decide``: run the decide service (see ``service.py``)."""

from services.decide.service import NAME, endpoints
from shared.bus import serve

if __name__ == "__main__":
    raise SystemExit(serve(NAME, endpoints))
