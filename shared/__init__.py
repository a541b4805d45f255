"""The common package every armplan process imports.

Importing it loads libqi first (``shared.libqi``): libqi and pinocchio bundle
different boost versions, and libqi must win (see that module). Then the
guard of the compiled IK modules runs (``shared.compiled``): a stale build
is not loaded.
"""

# isort: off
import shared.libqi  # first: before anything loads pinocchio
import shared.compiled

# isort: on

shared.compiled.guard()
