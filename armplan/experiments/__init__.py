"""The paper's experiments (Section V) on NAO, reproducible from the command line.

- ``similarity``: the similarity experiment (Fig. 14-15): the planned elbow
  against each subject's retargeted elbow on the 16 grid points, for the
  method and the two baselines.
- ``handover``: the human-robot collaboration task (Fig. 18): posture
  similarity (eq. 22-23) against human reference postures over time.
- ``measure_fit``: fitting the measure coefficients on training subjects.

Each concept has its own module; ``armplan experiment`` runs them.
"""
