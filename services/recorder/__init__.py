"""The recorder: chosen Zenoh key expressions to MCAP files, and their replay.

The algorithm lives apart from its thin Zenoh wrapper:

- ``routing.py``: which channel a received payload goes to;
- ``sink.py``: the writer thread (live MCAP, flushed at least every 0.2 s,
  rotation, derived Foxglove channels);
- ``replay.py``: a recording's messages back in time order, scaled;
- ``service.py``: :class:`Recorder`, the subscriptions and liveliness token;
- ``main.py``: ``python -m services.recorder``;
- ``control.py``: :class:`RecorderProcess`, for ``armplan demo``.

See ``docs/recording.md``.
"""

from services.recorder.control import RecorderProcess
from services.recorder.options import RecorderOptions
from services.recorder.service import Recorder

__all__ = ["Recorder", "RecorderOptions", "RecorderProcess"]
