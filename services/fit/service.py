"""The fit service: serves, fits and publishes the motion model on Zenoh.

Keys (namespace ``armplan`` by default):
    ``armplan/fit/model``         query: NoArguments -> the current MotionModel
    ``armplan/fit``               query: FitRequest -> the newly fitted model
    ``armplan/fit/model/update``  publication: the model at start (once the
                                  queryables and the liveliness token are
                                  declared), then each newly fitted one
                                  (the decide service swaps it in)

Run it with ``python -m services.fit [--model FILE] [--state-dir DIR]``
(``armplan up`` does, ``armplan up --model FILE`` passes ``--model``). It
reads demonstration files only inside ``$ARMPLAN_DEMOS_DIR`` (default: its
working directory) and keeps the model it serves in ``--state-dir``
(default: that same directory; one file per namespace) for a restart; see
``current_model.py``, ``model_state.py`` and ``demo_dir.py``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from services.fit.current_model import CurrentModel
from services.fit.demo_dir import demos_dir
from services.fit.model_state import (
    check_state_dir,
    say_other_state,
    start_model,
    state_file,
)
from shared.bus import Bus, Endpoint
from shared.bus.options import bus_config
from shared.bus.routes import FIT, FIT_MODEL
from shared.bus.runner import EndpointsFactory, Options, Served

NAME = "fit"


def add_options(parser: argparse.ArgumentParser) -> None:
    """The fit service's own options: ``--model`` and ``--state-dir``."""
    parser.add_argument(
        "--model",
        metavar="FILE",
        help="motion model to start with (default: the one served before a "
        "restart, kept in --state-dir, else the shipped default)",
    )
    parser.add_argument(
        "--state-dir",
        metavar="DIR",
        help="where the served model is kept for a restart (default: the "
        "demonstration directory, $ARMPLAN_DEMOS_DIR or the working directory)",
    )


def factory(args: argparse.Namespace) -> EndpointsFactory:
    """The endpoints factory for the parsed options; reads the start model now.

    Raises:
        ModelFileError: ``--model`` or the state file is no valid model.
        InvalidInputError: ``--state-dir`` is no folder it can write in.
        BusConfigError: the configuration (its namespace names the state
            file) is wrong.
    """
    namespace = bus_config(args).namespace  # --namespace too, as up passes it
    state_dir = Path(args.state_dir) if args.state_dir else demos_dir()
    check_state_dir(state_dir, given=args.state_dir is not None)
    state = state_file(state_dir, namespace)
    if args.model is None:
        say_other_state(state, namespace)
    start = start_model(args.model, state)

    def endpoints(bus: Bus) -> Served:
        """The fit service's endpoints; it publishes its start model once served.

        Published only after the queryables and the token are declared:
        published before, it was lost to a decide service that found no fit
        service and subscribed a moment later (it decided with the shipped
        model).
        """
        current = CurrentModel(bus, start, state)
        return Served(
            [Endpoint(FIT_MODEL, current.get), Endpoint(FIT, current.fit)],
            ready=current.publish,
        )

    return endpoints


OPTIONS = Options(add_options, factory)
