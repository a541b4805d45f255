"""The count-and-noun helper: singular for exactly one, plural otherwise."""

from __future__ import annotations

import numpy as np
import pytest

from shared.text.counted import agreeing, counted


@pytest.mark.parametrize(
    ("n", "text"), [(0, "0 messages"), (1, "1 message"), (2, "2 messages")]
)
def test_regular_noun_is_singular_only_for_one(n: int, text: str) -> None:
    assert counted(n, "message") == text


@pytest.mark.parametrize(
    ("n", "singular", "plural", "text"),
    [
        (1, "trajectory", "trajectories", "1 trajectory"),
        (3, "trajectory", "trajectories", "3 trajectories"),
        (0, "trajectory", "trajectories", "0 trajectories"),
        (1, "reach", "reaches", "1 reach"),
        (12, "reach", "reaches", "12 reaches"),
    ],
)
def test_irregular_plural_is_used_for_any_count_but_one(
    n: int, singular: str, plural: str, text: str
) -> None:
    assert counted(n, singular, plural) == text


def test_agreeing_gives_the_word_alone_for_verbs() -> None:
    assert agreeing(1, "was", "were") == "was"
    assert agreeing(2, "was", "were") == "were"
    assert agreeing(0, "was", "were") == "were"
    assert agreeing(1, "message") == "message"
    assert agreeing(5, "message") == "messages"


def test_numpy_integers_are_counts() -> None:
    assert counted(np.int64(1), "frame") == "1 frame"
    assert counted(np.intp(7), "frame") == "7 frames"


def test_large_counts_keep_their_digits() -> None:
    assert counted(1_000_001, "sample") == "1000001 samples"


def test_a_count_other_than_one_is_plural_and_never_raises() -> None:
    """The helpers write errors' text: an odd count still reads, never raises."""
    assert counted(-1, "message") == "-1 messages"
    assert agreeing(-1, "was", "were") == "were"
