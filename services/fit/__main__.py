"""``python -m services.fit``: run the fit service (see ``service.py``)."""

from services.fit.service import NAME, OPTIONS
from shared.bus import serve

if __name__ == "__main__":
    raise SystemExit(serve(NAME, OPTIONS))
