"""``python -m services.recorder``: run the recorder (see ``main.py``)."""

from services.recorder.main import main

if __name__ == "__main__":
    raise SystemExit(main())
