"""The fit service: serves, fits and publishes the motion model on Zenoh.

Keys (namespace ``armplan`` by default):
    ``armplan/fit/model``         query: NoArguments -> the current MotionModel
    ``armplan/fit``               query: FitRequest -> the newly fitted model
    ``armplan/fit/model/update``  publication: the model at start, then each
                                  newly fitted one (the decide service
                                  swaps it in)

Run it with ``python -m services.fit`` (``armplan up`` does). It reads
demonstration files only inside ``$ARMPLAN_DEMOS_DIR`` (default: its
working directory); see ``current_model.py`` and ``demo_dir.py``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from services.fit.current_model import CurrentModel
from shared.bus import Bus, Endpoint
from shared.bus.routes import FIT, FIT_MODEL

NAME = "fit"


def endpoints(bus: Bus) -> Sequence[Endpoint[Any, Any]]:
    """The fit service's endpoints; publishes the model it starts with."""
    current = CurrentModel(bus)
    current.publish()
    return [Endpoint(FIT_MODEL, current.get), Endpoint(FIT, current.fit)]
