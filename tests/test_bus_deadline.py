"""A caller's deadline as a service sees it, and the margin an answer needs."""

from __future__ import annotations

import time

from services.planner.waiting import Waiting
from shared.bus.deadline import REPLY_MARGIN, Due


def due_in(seconds: float) -> Due:
    """A caller that stops waiting ``seconds`` [s] from now."""
    return Due(time.monotonic() + seconds, seconds)


def test_an_answer_within_the_margin_of_the_deadline_is_too_late() -> None:
    """Not yet passed, but an answer sent now would travel back too late."""
    near = due_in(REPLY_MARGIN / 2)
    assert not near.passed and near.too_late
    far = due_in(REPLY_MARGIN + 5.0)
    assert not far.passed and not far.too_late
    gone = due_in(-0.001)
    assert gone.passed and gone.too_late


def test_a_request_is_abandoned_only_when_every_caller_is_too_late() -> None:
    """Two callers of one id: gone only once the later one is within the
    margin; a caller without a deadline always waits."""
    waiting = Waiting()
    with waiting.caller("id", due_in(REPLY_MARGIN / 2)):
        assert waiting.all_gone("id", None)
        with waiting.caller("id", due_in(REPLY_MARGIN + 5.0)):
            assert not waiting.all_gone("id", None)
        with waiting.caller("id", None):
            assert not waiting.all_gone("id", None)
    assert waiting.all_gone(None, due_in(REPLY_MARGIN / 2))
    assert not waiting.all_gone(None, None)


def test_a_caller_whose_session_ended_is_gone_whatever_its_deadline() -> None:
    """A caller still within its deadline, but whose session has ended, waits
    no more; one whose session is not known (not said, or not ended) waits
    until its deadline; the request is abandoned only when every caller is
    gone."""
    ended = {"a1"}.__contains__
    far = REPLY_MARGIN + 60.0
    a1, b2 = due_in(far)._replace(session="a1"), due_in(far)._replace(session="b2")
    waiting = Waiting()
    with waiting.caller("id", a1):
        assert waiting.all_gone("id", a1, ended)
        assert not waiting.all_gone("id", a1)  # the ended sessions not known
        with waiting.caller("id", b2):
            assert not waiting.all_gone("id", a1, ended)
        with waiting.caller("id", due_in(far)):  # its session not said
            assert not waiting.all_gone("id", a1, ended)
    assert waiting.all_gone(None, a1, ended)
    assert not waiting.all_gone(None, b2, ended)
