"""The command-line arguments that put a child process on the launcher's bus.

Every service (``python -m services.<name>``) and the bridge (``python -m
bridge.serve``) that ``armplan up`` or ``demo`` starts gets the launcher's
settings: its file (``--config``), its router endpoints (``--connect``) and
its namespace (``--namespace``). The namespace is always passed, not only
when ``up --namespace`` gave it: the child then serves in the namespace the
launcher waits on, whatever the file says when it reads it (a restarted
child reads it again), as the recorder's command line does
(``services.recorder.control.recorder_command``).
"""

from __future__ import annotations

from shared.bus import BusConfig


def bus_args(config: BusConfig) -> list[str]:
    """``--config FILE`` (if from a file), ``--connect E`` each, ``--namespace NS``.

    Example: ``["--connect", "tcp/127.0.0.1:7447", "--namespace", "armplan"]``
    for the built-in defaults.
    """
    args = [] if config.file is None else ["--config", config.file]
    for endpoint in config.endpoints:
        args += ["--connect", endpoint]
    return [*args, "--namespace", config.namespace]
