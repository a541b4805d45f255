"""armplan processes: one package each; the algorithm apart from its Zenoh wrapper."""

import shared  # noqa: F401  (first: the guard of the compiled modules)
