"""``python -m services.ik``: run the IK service (see ``service.py``)."""

from services.ik.service import NAME, endpoints
from shared.bus import serve

if __name__ == "__main__":
    raise SystemExit(serve(NAME, endpoints))
