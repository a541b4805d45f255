"""The motion model: what ``armplan fit`` writes and the decision reads.

The message itself lives in ``shared.messages.motion_model`` (it crosses
processes: the fit service serves and publishes it); this module keeps the
names the fitting code uses and how it rounds the tables. A file of another
``MODEL_VERSION`` is refused (``model_file``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from shared.messages.motion_model import (
    MODEL_VERSION,
    ArmLengths,
    MotionModel,
    VariableFit,
)

__all__ = [
    "MODEL_VERSION",
    "UNITS",
    "UNOBSERVED_RATE",
    "ArmLengths",
    "MotionModel",
    "VariableFit",
    "rounded",
]

#: Units of the variables, in ``VARIABLES`` order.
UNITS = ("rad", "arm lengths", "rad", "arm lengths", "rad")
#: Rate given to a variable the demonstrations never observe [1/unit].
UNOBSERVED_RATE = 2.0


def rounded(values: np.ndarray, digits: int = 10) -> Any:
    """Nested lists of ``values`` rounded to ``digits`` significant digits."""
    flat = [float(f"{v:.{digits}g}") if math.isfinite(v) else v for v in values.ravel()]
    return np.array(flat).reshape(values.shape).tolist()
