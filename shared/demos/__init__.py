"""Human demonstrations: a synthetic set, motion-capture import, MCAP files.

- ``synthetic``: the paper's protocol (16 subjects, 4 x 4 grid, 5 trials,
  100 Hz) made by a human reach model (``reach_model``) with per-subject arm
  sizes from anthropometric tables (``anthropometry``).
- ``c3d_import``, ``csv_import``: recorded markers (``markers`` maps them);
  a C3D file's structure is checked first (``c3d_layout``) and ezc3d reads it
  in a child process (``c3d_reading``); a CSV file's table (rows, columns,
  trials, cells) is read by ``csv_table``.
- ``retarget``: human arm data to NAO, segment directions kept.
- ``demo_file``: demonstration MCAP files (``DemoSubject``, ``DemoSample``).
"""

from shared.demos.anthropometry import Subject
from shared.demos.demo_file import read_demos, write_demos
from shared.demos.retarget import ArmSize, nao_arm_size, retarget
from shared.demos.synthetic import synthesize
from shared.demos.trial import DemoSet, Trial

__all__ = [
    "ArmSize",
    "DemoSet",
    "Subject",
    "Trial",
    "nao_arm_size",
    "read_demos",
    "retarget",
    "synthesize",
    "write_demos",
]
