"""A trial read twice: refused, since it would count twice in a fit.

Two demonstration files can hold one recording twice: a copy of a file
under another name, or a CSV and a C3D export of one session imported
apart. And two imports each number their trials from 0, so one subject's
trial 3 of one arm can be in two files as two recordings: the experiments
tell reaches off the grid apart by (subject, arm, trial), and would average
the two as one. ``Register`` refuses both, naming both files. One number on
the two arms is two reaches (a CSV of both arms imported once per arm).
"""

from __future__ import annotations

import numpy as np

from shared.demos.sample_lines import line_evidence, trial_span
from shared.demos.trial import Trial
from shared.errors import DemoFileError

#: Farthest apart two trials' positions [m] and times [s] may be, at every
#: sample, to be one recording: a CSV and a C3D export of a session differ
#: by their rounding (micrometres), two takes by the markers' noise (mm).
SAME_SAMPLES = 1e-4


def same_samples(first: Trial, again: Trial) -> bool:
    """Whether two trials hold one recording.

    They do when their times [s] and positions [m] agree within
    ``SAME_SAMPLES``, sample for sample (shapes (n,) and (n, 3)).
    """
    if len(first.times) != len(again.times):
        return False
    middle = len(first.times) // 2  # a quick look first: most trials differ there
    if np.abs(first.wrist[middle] - again.wrist[middle]).max() > SAME_SAMPLES:
        return False
    return all(
        np.allclose(a, b, rtol=0.0, atol=SAME_SAMPLES)
        for a, b in zip(
            (first.times, first.shoulder, first.elbow, first.wrist),
            (again.times, again.shoulder, again.elbow, again.wrist),
            strict=True,
        )
    )


class Register:
    """The trials read so far, each with the file it came from."""

    def __init__(self) -> None:
        #: Files by (subject, arm, trial number).
        self._by_name: dict[tuple[str, str, int], str] = {}
        #: Trials by sample count: the candidates for ``same_samples``.
        self._by_count: dict[int, list[tuple[Trial, str]]] = {}

    def add(self, trial: Trial, where: str, synthetic: bool = False) -> None:
        """Note ``trial``, read from file ``where``.

        ``synthetic``: the file is ``armplan demos synth``'s (the advice of a
        refusal differs).

        Raises:
            DemoFileError: (of file ``where``) if the same samples
                (``same_samples``) were read before, under any name, or the
                subject's trial number of this arm was, naming both files.
        """
        named = f"trial {trial.trial} of subject {trial.subject!r}"
        named += trial_span(trial.lines)
        lines = line_evidence(trial.lines, 0, len(trial.times) - 1)
        arm = trial.arm.value
        twins = self._by_count.setdefault(len(trial.times), [])
        for first, there in twins:
            if same_samples(first, trial):
                raise DemoFileError(
                    where,
                    f"{named} holds the samples of trial {first.trial} of subject "
                    f"{first.subject!r}{trial_span(first.lines)} "
                    f"{self._in(there, where)} (positions within "
                    f"{SAME_SAMPLES * 1000:g} mm): one recording given twice (a "
                    "copy, or two exports of one session) would count twice",
                    trial=trial.trial,
                    subject=trial.subject,
                    duplicate=there,
                    **lines,
                )
        key = (trial.subject, arm, trial.trial)
        if key in self._by_name:
            there = self._by_name[key]
            raise DemoFileError(
                where,
                f"{named} ({arm} arm) is also {self._in(there, where)}, another "
                "recording under the same number "
                f"{self._advice(trial.subject, arm, synthetic)}",
                trial=trial.trial,
                subject=trial.subject,
                duplicate=there,
                **lines,
            )
        self._by_name[key] = where
        twins.append((trial, where))

    def _advice(self, subject: str, arm: str, synthetic: bool) -> str:
        """What to do about a trial number used twice, by where the file came from."""
        if synthetic:
            return (
                "(each `armplan demos synth` set numbers its trials from 0): a "
                "synthetic set is read alone; make one with more --subjects or "
                "--trials instead"
            )
        first = self._next(subject, arm)
        return (
            "(each `armplan demos import` numbers its trials from 0): import the "
            f"files in one `armplan demos import`, or number this file's from "
            f"{first} (`armplan demos import --first-trial {first}`)"
        )

    def _next(self, subject: str, arm: str) -> int:
        """The next free trial number of the subject's ``arm``."""
        return 1 + max(
            n for name, side, n in self._by_name if (name, side) == (subject, arm)
        )

    @staticmethod
    def _in(there: str, where: str) -> str:
        return "earlier in this file" if there == where else f"in {there}"
