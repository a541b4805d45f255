"""armplan processes: one package each; the algorithm apart from its Zenoh wrapper."""
