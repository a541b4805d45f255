"""The common package every armplan process imports.

Importing it loads libqi first (``shared.libqi``): libqi and pinocchio bundle
different boost versions, and libqi must win (see that module).
"""

import shared.libqi  # noqa: F401  (first: before anything loads pinocchio)
