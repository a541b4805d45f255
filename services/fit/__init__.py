"""The motion model (paper Section III.A-B): variables, densities, network.

- ``variables``: the five motion variables S_R, E_P, E_R, W_P, W_R.
- ``exponential``: their exponential densities (maximum likelihood rate,
  leave-one-out cross-validation); ``discretize``: their states.
- ``network``: the Bayesian network's structure; ``conditionals``: its
  tables, learned from the demonstrations.
- ``fitting``: demonstrations to a ``MotionModel`` (``model``), stored with
  ``model_file``; ``default``: the fitted model shipped with armplan.
"""

from services.fit.default import default_model, default_model_path
from services.fit.fitting import fit_model
from services.fit.model import MODEL_VERSION, MotionModel
from services.fit.model_file import load_model, save_model

__all__ = [
    "MODEL_VERSION",
    "MotionModel",
    "default_model",
    "default_model_path",
    "fit_model",
    "load_model",
    "save_model",
]
