"""AnswerOnce: a request repeated by id is worked on once, its answer shared."""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

import pytest

from services.planner.answer_once import AnswerOnce
from shared.errors import InvalidInputError


class Work:
    """Counts its runs; each run may wait for a gate and may fail."""

    def __init__(self, gate: threading.Event | None = None, fail: bool = False):
        self.runs, self.gate, self.fail = 0, gate, fail

    def __call__(self) -> list[int]:
        self.runs += 1
        if self.gate is not None:
            assert self.gate.wait(5.0)
        if self.fail:
            raise RuntimeError("no plan")
        return [self.runs]


def test_a_repeat_during_the_work_waits_for_the_same_answer() -> None:
    once: AnswerOnce[str, list[int]] = AnswerOnce()
    gate = threading.Event()
    work = Work(gate)
    with ThreadPoolExecutor(4) as pool:
        answers = [pool.submit(once.answer, "id-1", "reach", work) for _ in range(4)]
        gate.set()
        results = [a.result(5.0) for a in answers]
    assert work.runs == 1
    assert all(r is results[0] for r in results)  # the very same object


def test_a_later_repeat_gets_the_kept_answer_and_none_means_no_id() -> None:
    once: AnswerOnce[str, list[int]] = AnswerOnce()
    work = Work()
    first = once.answer("id-1", "reach", work)
    assert once.answer("id-1", "reach", work) is first and work.runs == 1
    once.answer(None, "reach", work)
    once.answer(None, "reach", work)
    assert work.runs == 3


def test_an_id_reused_for_another_request_is_refused() -> None:
    once: AnswerOnce[str, list[int]] = AnswerOnce()
    once.answer("id-1", "reach", Work())
    with pytest.raises(InvalidInputError, match="'id-1' was used for another"):
        once.answer("id-1", "wave", Work())


def test_a_failure_reaches_the_waiters_and_is_then_forgotten() -> None:
    once: AnswerOnce[str, list[int]] = AnswerOnce()
    gate = threading.Event()
    failing = Work(gate, fail=True)
    with ThreadPoolExecutor(2) as pool:
        first = pool.submit(once.answer, "id-1", "reach", failing)
        while failing.runs == 0:  # the first one is at work
            threading.Event().wait(0.01)
        repeat = pool.submit(once.answer, "id-1", "reach", failing)
        gate.set()
        for attempt in (first, repeat):
            with pytest.raises(RuntimeError, match="no plan"):
                attempt.result(5.0)
    assert failing.runs == 1
    assert once.answer("id-1", "reach", Work()) == [1]  # asked again: worked on


def test_only_the_last_answers_are_kept() -> None:
    once: AnswerOnce[str, list[int]] = AnswerOnce(keep=2)
    work = Work()
    for key in ("a", "b", "c"):
        once.answer(key, key, work)
    once.answer("c", "c", work)
    once.answer("a", "a", work)  # forgotten: worked on again
    assert work.runs == 4


def test_an_id_is_forgotten_after_the_hold_time() -> None:
    """Kept for ``hold`` seconds from its first arrival, then worked on anew."""
    now = [100.0]
    once: AnswerOnce[str, list[int]] = AnswerOnce(hold=60.0, clock=lambda: now[0])
    work = Work()
    first = once.answer("id-1", "reach", work)
    now[0] = 159.9
    assert once.answer("id-1", "reach", work) is first and len(once) == 1
    now[0] = 160.1
    assert len(once) == 0
    assert once.answer("id-1", "reach", work) == [2] and work.runs == 2


def test_requests_are_told_apart_by_their_fingerprint() -> None:
    """Only a digest is kept: equal fingerprints are repeats, others refused."""
    once: AnswerOnce[dict[str, float], list[int]] = AnswerOnce(
        fingerprint=lambda r: f"{r['x']!r}"
    )
    work = Work()
    first = once.answer("id-1", {"x": 0.1}, work)
    assert once.answer("id-1", {"x": 0.1}, work) is first
    with pytest.raises(InvalidInputError, match="used for another request"):
        once.answer("id-1", {"x": 0.1 + 1e-15}, work)
    assert work.runs == 1


def test_the_kept_answers_stay_within_their_weight_budget() -> None:
    """Past the budget the oldest answers go first; the newest always stays."""
    once: AnswerOnce[str, list[int]] = AnswerOnce(weight=len, budget=5)
    for key, size in (("a", 2), ("b", 2), ("c", 1)):
        once.answer(key, key, lambda size=size: [0] * size)
    assert once.weighed() == 5  # at the budget: all kept
    c = once.answer("c", "c", lambda: [9])
    once.answer("d", "d", lambda: [0] * 3)  # 8 > 5: a's and b's answers go
    assert once.weighed() == 4 and len(once) == 4  # their ids stay
    assert once.answer("c", "c", lambda: [9]) is c
    big = once.answer("e", "e", lambda: [0] * 9)  # alone over the budget
    assert once.weighed() == 9
    assert once.answer("e", "e", lambda: [1]) is big  # still answers repeats


def test_a_repeat_whose_answer_went_is_still_known_as_a_repeat() -> None:
    """Its id stays: ``again`` answers it (no second ``work``), without
    ``again`` it is refused, and reusing the id for another request is too."""
    once: AnswerOnce[str, list[int]] = AnswerOnce(weight=len, budget=1)
    work = Work()
    once.answer("a", "reach", work)
    once.answer("b", "wave", lambda: [0])  # a's answer goes
    again = Work()
    assert once.answer("a", "reach", work, again=again) == [1]
    assert work.runs == 1 and again.runs == 1
    with pytest.raises(InvalidInputError, match="'a' was answered already"):
        once.answer("a", "reach", work)
    with pytest.raises(InvalidInputError, match="'a' was used for another"):
        once.answer("a", "wave", work, again=again)
    assert work.runs == 1 and again.runs == 1


def test_ids_outlast_a_busy_minute() -> None:
    """At 170 plans a second a minute brings 10 200 ids: all are remembered."""
    once: AnswerOnce[str, list[int]] = AnswerOnce(weight=len, budget=100)
    for k in range(10_200):
        once.answer(f"id-{k}", f"reach {k}", lambda: [0])
    assert len(once) == 10_200 and once.weighed() == 100
    with pytest.raises(InvalidInputError, match="used for another"):
        once.answer("id-0", "wave", lambda: [1])


def test_an_answer_in_the_making_is_not_forgotten_for_the_budget() -> None:
    """Only finished answers are dropped: a repeat of a running one still waits."""
    once: AnswerOnce[str, list[int]] = AnswerOnce(weight=len, budget=1)
    gate = threading.Event()
    slow = Work(gate)
    with ThreadPoolExecutor(2) as pool:
        first = pool.submit(once.answer, "slow", "reach", slow)
        while slow.runs == 0:
            threading.Event().wait(0.01)
        once.answer("quick", "quick", lambda: [0, 0])  # over the budget
        repeat = pool.submit(once.answer, "slow", "reach", slow)
        gate.set()
        assert repeat.result(5.0) is first.result(5.0)
    assert slow.runs == 1


def test_work_outlasting_the_hold_does_not_touch_a_newer_attempt() -> None:
    """An id forgotten while its work runs and asked anew: the first work's
    end (answer or failure) leaves the new entry and the budget alone."""
    now = [0.0]
    once: AnswerOnce[str, list[int]] = AnswerOnce(
        hold=60.0, clock=lambda: now[0], weight=len, budget=100
    )
    gates = [threading.Event(), threading.Event()]
    slow = [Work(gates[0]), Work(gates[1], fail=True)]
    with ThreadPoolExecutor(2) as pool:
        first = pool.submit(once.answer, "id", "reach", slow[0])
        while slow[0].runs == 0:
            threading.Event().wait(0.01)
        now[0] = 61.0  # forgotten while it runs; the caller asks again
        second = pool.submit(once.answer, "id", "reach", slow[1])
        while slow[1].runs == 0:
            threading.Event().wait(0.01)
        gates[0].set()
        assert first.result(5.0) == [1]
        assert once.weighed() == 0  # the first answer's entry is gone
        assert len(once) == 1  # the new attempt's entry stays
        gates[1].set()
        with pytest.raises(RuntimeError):
            second.result(5.0)
    assert once.weighed() == 0 and len(once) == 0
