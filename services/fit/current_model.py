"""The fit service's current motion model: served, replaced by a fit, published.

It starts as the shipped default model and is published at once, so a
decide service that is already running follows a restarted fit service.
Each fit replaces it and publishes the new one on ``<ns>/fit/model/update``;
the decide service swaps it in without a restart. The model lives in memory:
a restarted fit service serves the default again (and says so by publishing
it).
"""

from __future__ import annotations

import logging
import threading

from services.fit.default import default_model
from services.fit.demo_dir import demo_file, demos_dir
from services.fit.fitting import fit_model
from shared.bus import Bus, NoArguments
from shared.bus.routes import MODEL_TOPIC
from shared.demos import read_demos
from shared.messages import FitRequest, MotionModel

log = logging.getLogger("armplan.fit")


class CurrentModel:
    """The model the fit service serves now.

    Args:
        bus: Where new models are published.
        model: The model to start with; default: the shipped one.
    """

    def __init__(self, bus: Bus, model: MotionModel | None = None) -> None:
        self._bus = bus
        self._model = model or default_model()
        self._lock = threading.Lock()

    def get(self, request: NoArguments) -> MotionModel:
        """The current model (the ``fit/model`` query)."""
        return self._model

    def publish(self) -> None:
        """Publish the current model on ``fit/model/update``."""
        with self._lock:
            self._bus.publish(MODEL_TOPIC, self._model)

    def fit(self, request: FitRequest) -> MotionModel:
        """Fit a model to the request's files, make it current, publish it.

        Raises:
            InvalidInputError: a file name outside the demonstration directory,
                or demonstrations that cannot be fitted.
            DemoFileError: a file that is missing or not a demonstration file.
        """
        root = demos_dir()
        paths = [demo_file(name, root) for name in request.files]
        model = fit_model(
            read_demos(paths),
            bins=request.bins,
            smoothing=request.smoothing,
            sources=request.files,
        )
        with self._lock:  # current and published stay in the same order
            self._model = model
            self._bus.publish(MODEL_TOPIC, model)
        log.info("new model fitted on %d samples and published", model.samples)
        return model
