"""libqi's Python bindings (``qi``), and the import order they need.

``qi`` 3.1.5 bundles boost 1.83; pinocchio (cmeel) loads boost 1.90. Some
boost symbols are GNU-unique (the ``boost::system`` error categories that
``boost_filesystem`` defines), so whichever library is loaded first serves
them to the whole process. With pinocchio's loaded first, libqi crashes
(double free, segmentation fault) when a connection drops, for instance when
the robot dies mid-trajectory. A process that uses both must import ``qi``
before anything imports pinocchio. Every armplan module imports pinocchio
through ``shared.robot``, and ``shared/__init__.py`` imports this module
first, so any process that imports ``shared`` before pinocchio is safe; the
warning below names the one that does not.

libqi's warning that no ``qi.Application`` was made (``[W] ...
qi.path.sdklayout: No Application was created, trying to deduce paths``) is
filtered out: armplan makes none on purpose (it finds no files through
libqi), and C++ wrote the line on standard output, ahead of what a reader
of ``armplan sim``'s output waits for (its ready line).
"""

from __future__ import annotations

import sys
import warnings

#: True if pinocchio was already loaded when ``qi`` was: the unsafe order.
LOADED_AFTER_PINOCCHIO = "pinocchio" in sys.modules and "qi" not in sys.modules

import qi  # noqa: E402

#: libqi's log categories armplan silences (see above).
SILENCED = ("qi.path.sdklayout",)
qi.logging.setFilters(":".join(f"-{category}" for category in SILENCED))

if LOADED_AFTER_PINOCCHIO:
    warnings.warn(
        "libqi was loaded after pinocchio: a dropped robot connection may crash "
        "this process; import shared (or qi) before pinocchio",
        RuntimeWarning,
        stacklevel=2,
    )

__all__ = ["LOADED_AFTER_PINOCCHIO", "SILENCED", "qi"]
