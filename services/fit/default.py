"""The fitted default motion model shipped inside the package.

It is fitted on the synthetic demonstration set with seed 0. Regenerate it
from the repository root with:

    armplan demos synth -o /tmp/armplan-demos.mcap --seed 0
    armplan fit /tmp/armplan-demos.mcap -o services/fit/default_model.json

(``docs/decision.md`` explains the model.)
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from pathlib import Path

from services.fit.model import MotionModel
from services.fit.model_file import load_model

#: The default model's file name inside ``services.fit``.
DEFAULT_MODEL_FILE = "default_model.json"


def default_model_path() -> Path:
    """Where the shipped default model lives."""
    return Path(str(resources.files("services.fit").joinpath(DEFAULT_MODEL_FILE)))


@cache
def default_model() -> MotionModel:
    """The shipped default model (read once)."""
    return load_model(default_model_path())
