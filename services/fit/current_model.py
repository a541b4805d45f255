"""The fit service's current motion model: served, replaced by a fit, published.

It starts as the model ``model_state.start_model`` picks (``--model FILE``,
else the one served before a restart, else the shipped default) and is
published at once, so a decide service that is already running follows a
restarted fit service. Each fit replaces it, keeps it in the state file
(``model_state``) and publishes it on ``<ns>/fit/model/update``; the decide
service swaps it in without a restart.

One fit runs at a time: a second request while one runs is refused at once
(``service_busy``), so an older request's model can never replace a newer
one's (a slow fit sent first used to be installed 36 s after a quick one
sent 2 s later). A fit that ends after its caller stopped waiting is not
installed (``request_timeout``): no one was told of the model, so it must
not change every plan (it used to be served 36 s after its caller's 5 s
timeout). The caller's deadline is checked after the demonstrations are
read and after each step of the fit (``fit_model``'s progress, one per
trial), so a fit whose caller stopped waiting stops there instead of running
to its end: such a fit used to hold the one-fit lock for 11 s after its
caller's 4 s timeout, refusing the caller's retry as busy with "its model
is served when it ends", which it never was. A fit refused while one past
its deadline still runs says that model will not be served.

A fit whose caller's session has ended (its ``armplan fit --remote``
interrupted with Ctrl-C, or killed: its caller token went,
``shared.bus.gone_callers``) is abandoned at the same checks and before the
model is installed, whatever its deadline: it used to run on and replace
the served model minutes after the lab had taken it as cancelled.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from pathlib import Path

from services.fit.decidable import check_decidable
from services.fit.default import default_model, default_model_path
from services.fit.demo_dir import demo_file, demos_dir
from services.fit.fitting import fit_model
from services.fit.model_state import StartModel, digest, keep
from shared.bus import Bus, NoArguments
from shared.bus.deadline import Due, current_due
from shared.bus.routes import FIT, MODEL_TOPIC
from shared.demos import read_demos
from shared.errors import InvalidInputError, RequestTimeoutError, ServiceBusyError
from shared.messages import FitRequest, MotionModel

log = logging.getLogger("armplan.fit")

#: Whether the session of this id (``Due.session``) has ended; ``None``: not said.
CallerGone = Callable[[str | None], bool]


class CurrentModel:
    """The model the fit service serves now.

    Args:
        bus: Where new models are published.
        start: The model to start with and where it came from; default: the
            shipped one.
        state: The state file each new model is kept in; ``None``: none.
    """

    def __init__(
        self, bus: Bus, start: StartModel | None = None, state: Path | None = None
    ) -> None:
        start = start or StartModel(
            default_model(), f"shipped default {default_model_path()}"
        )
        self._bus = bus
        bus.caller_gone(None)  # watch callers' sessions end from the start
        self._model = start.model
        self._state = state
        self._lock = threading.Lock()
        self._fitting = threading.Lock()
        #: The running fit's caller's deadline (``None``: none or no fit).
        self._running: Due | None = None
        log.info(
            "serving model %s (%d samples, primitives %s) from %s",
            digest(start.model),
            start.model.samples,
            ", ".join(start.model.primitives),
            start.source,
        )
        if start.given:
            keep(start.model, state)  # a restart without --model serves it too

    @property
    def fitting(self) -> bool:
        """Whether a fit is running now."""
        return self._fitting.locked()

    def get(self, request: NoArguments) -> MotionModel:
        """The current model (the ``fit/model`` query)."""
        return self._model

    def publish(self) -> None:
        """Publish the current model on ``fit/model/update``."""
        with self._lock:
            self._bus.publish(MODEL_TOPIC, self._model)

    def fit(self, request: FitRequest) -> MotionModel:
        """Fit a model to the request's files, make it current, publish it.

        Raises:
            InvalidInputError: a file name outside the demonstration directory,
                demonstrations that cannot be fitted, or a fitted model the
                decision cannot use (the model is not installed).
            DemoFileError: a file that is missing or not a demonstration file.
            ServiceBusyError: another fit is running (nothing done).
            RequestTimeoutError: the fit ended after its caller stopped
                waiting, or its caller's session ended (the model is not
                installed).
        """
        key = FIT.key(self._bus.config.namespace)
        if not self._fitting.acquire(blocking=False):
            raise ServiceBusyError(FIT.service, key=key, queued=0, why=self._busy())
        due = current_due()
        self._running = due
        try:
            return self._fit(request, key, due)
        finally:
            self._running = None
            self._fitting.release()

    def _busy(self) -> str:
        """Why a fit is refused while another runs, and what becomes of that one."""
        running = self._running
        left = None if running is None else _caller_left(running, self._bus.caller_gone)
        if left is not None:
            return (
                f"a fit is running (one at a time) whose {left}: its model will "
                "not be served, and it stops at its next step"
            )
        return "a fit is running (one at a time); its model is served when it ends"

    def _fit(self, request: FitRequest, key: str, due: Due | None) -> MotionModel:
        """:meth:`fit`, with the fitting lock held.

        Raises:
            RequestTimeoutError: ``due`` passed, or the caller's session
                ended, after the demonstrations were read, at a step of the
                fit, or by its end.
        """
        root = demos_dir()
        paths = [demo_file(name, root) for name in request.files]
        demos = read_demos(paths)
        gone = self._bus.caller_gone
        _check_caller(due, gone, request, key, "reading the demonstrations")

        def progress(done: int, total: int) -> None:
            after = f"step {done} of {total} of the fit"
            _check_caller(due, gone, request, key, after)

        model = fit_model(
            demos,
            bins=request.bins,
            smoothing=request.smoothing,
            sources=request.files,
            progress=None if due is None else progress,
        )
        _check_decidable(model, request)
        left = None if due is None else _caller_left(due, gone)
        if due is not None and left is not None:
            log.warning(
                "model %s fitted on %s after its %s: not installed",
                digest(model),
                ", ".join(request.files),
                left,
            )
            raise _left_error(due, left, key, "fitting")
        with self._lock:  # current, kept and published stay in the same order
            self._model = model
            keep(model, self._state)
            self._bus.publish(MODEL_TOPIC, model)
        log.info(
            "serving model %s fitted on %d samples of %s; published",
            digest(model),
            model.samples,
            ", ".join(request.files),
        )
        if model.weights is not None and not model.weights.trusted:
            log.warning("model %s: %s", digest(model), model.weights.untrusted())
        return model


def _check_caller(
    due: Due | None, gone: CallerGone, request: FitRequest, key: str, after: str
) -> None:
    """Stop a fit whose caller left; ``after``: the step just done.

    ``gone``: whether a caller's session has ended (``Bus.caller_gone``).

    Raises:
        RequestTimeoutError: ``due`` is (nearly) past, or the caller's
            session ended; nothing is installed.
    """
    left = None if due is None else _caller_left(due, gone)
    if due is None or left is None:
        return
    log.warning(
        "fit on %s stopped after %s: its %s; no model installed",
        ", ".join(request.files),
        after,
        left,
    )
    raise _left_error(due, left, key, after)


def _caller_left(due: Due, gone: CallerGone) -> str | None:
    """How the caller due by ``due`` left, e.g. "caller stopped waiting (5.0 s)".

    ``None``: it still waits. A deadline passed is said first: a caller
    that stopped waiting then closes its session (``armplan fit --remote``
    exits on request_timeout), and was said to be "interrupted or killed".
    Its session ended (Ctrl-C, killed) before its deadline, which may be far
    off, is said as such.
    """
    if due.too_late:
        return f"caller stopped waiting ({due.budget:.1f} s)"
    if gone(due.session):
        return "caller's session ended (interrupted or killed)"
    return None


def _left_error(due: Due, left: str, key: str, after: str) -> RequestTimeoutError:
    """The error of a fit stopped after ``after`` because its caller ``left``.

    A deadline passed keeps the plain timeout message the client adds its
    advice to; a session ended says so (no one may read it).
    """
    if due.too_late:
        return RequestTimeoutError(FIT.service, key=key, timeout=due.budget)
    return RequestTimeoutError(
        FIT.service,
        key=key,
        timeout=due.budget,
        message=f"the {left} after {after}: the fit was abandoned and its "
        "model is not served",
    )


def _check_decidable(model: MotionModel, request: FitRequest) -> None:
    """Refuse a fitted model the decision cannot use, naming why.

    Raises:
        InvalidInputError: (field ``smoothing``) the model is not installed.
    """
    try:
        check_decidable(model)
    except InvalidInputError as error:
        log.warning(
            "model %s fitted on %s cannot decide: not installed (%s)",
            digest(model),
            ", ".join(request.files),
            error.message,
        )
        raise InvalidInputError(
            f"the model fitted on {', '.join(request.files)} (bins {request.bins}, "
            f"smoothing {request.smoothing!r}) is not served, the current one "
            f"stays: {error.message}",
            field="smoothing",
            table=error.evidence.get("table"),
        ) from None
