"""One subject name in several files: the same person's arm, measured twice.

An imported subject's upper arm and forearm are medians of marker distances
over a trial's frames, so two imports of one person (two sessions, or a CSV
and a C3D export of one session) differ by millimetres, and by more when the
markers were placed again. ``armplan demos import`` (across its files) and
``read_demos`` (across demonstration files) take two arms of one name for
one person within ``SAME_ARM``, and refuse two people under one name beyond
it.
"""

from __future__ import annotations

from shared.demos.anthropometry import Subject

#: Largest difference of a segment's measured length between two files of
#: one person, relative to the first (marker placement moves from session to
#: session; two adults' arms differ by more).
SAME_ARM = 0.1


def same_arm(first: Subject, again: Subject) -> bool:
    """Whether ``again``'s upper arm and forearm [m] are ``first``'s.

    Each within ``SAME_ARM`` of ``first``'s length.
    """
    return all(
        abs(length - seen) <= SAME_ARM * seen
        for seen, length in (
            (first.upper_arm, again.upper_arm),
            (first.forearm, again.forearm),
        )
    )
