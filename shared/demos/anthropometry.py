"""Arm sizes of synthetic subjects, from anthropometric tables.

Segment lengths are fractions of stature H, between joint centres
(Drillis and Contini 1966, as tabulated by Winter 2009, Fig. 4.1):

    upper arm  (glenohumeral - elbow joint centre)  0.186 H
    forearm    (elbow - wrist joint centre)         0.146 H

Statures are drawn for a group of young adults like the paper's (16
subjects, mean age 21.5): men N(1.756 m, 0.069 m), women N(1.629 m,
0.064 m), close to the ANSUR II survey of young adults (Gordon et al. 2014).
Individuals differ from the table's ratios; each subject's two ratios are
scaled by N(1, 0.03) each (about the spread between individuals that
Drillis and Contini report).

Sources:
    Drillis R., Contini R. (1966). Body segment parameters. Technical report
        1166-03, Office of Vocational Rehabilitation, New York University.
    Winter D. A. (2009). Biomechanics and Motor Control of Human Movement,
        4th ed., Wiley, chapter 4 (segment lengths as fractions of height).
    Gordon C. C. et al. (2014). 2012 Anthropometric Survey of U.S. Army
        Personnel (ANSUR II). Technical report NATICK/TR-15/007.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

#: Upper arm length as a fraction of stature (Winter 2009, Fig. 4.1).
UPPER_ARM_RATIO = 0.186
#: Forearm length as a fraction of stature (Winter 2009, Fig. 4.1).
FOREARM_RATIO = 0.146
#: Stature of young men and women: (mean [m], standard deviation [m]).
STATURE_MEN = (1.756, 0.069)
STATURE_WOMEN = (1.629, 0.064)
#: Spread of an individual's segment ratios about the table's (relative).
RATIO_SPREAD = 0.03


class Subject(NamedTuple):
    """One (synthetic or measured) person's arm.

    Attributes:
        name: Identifier, e.g. ``"S01"``.
        stature: Height H [m] (0 if unknown).
        upper_arm: Shoulder-to-elbow length L_u [m].
        forearm: Elbow-to-wrist length L_f [m].
    """

    name: str
    stature: float
    upper_arm: float
    forearm: float

    @property
    def arm_length(self) -> float:
        """L_u + L_f [m]."""
        return self.upper_arm + self.forearm


def subject_from_stature(name: str, stature: float) -> Subject:
    """A subject with the table's segment ratios for stature ``stature`` [m]."""
    return Subject(name, stature, UPPER_ARM_RATIO * stature, FOREARM_RATIO * stature)


def draw_subjects(count: int, rng: np.random.Generator) -> list[Subject]:
    """``count`` subjects, alternately men and women, with individual ratios.

    Args:
        count: How many subjects.
        rng: The seeded random generator to draw from.

    Returns:
        Subjects named ``S01``, ``S02``, ...
    """
    subjects = []
    for index in range(count):
        mean, sd = STATURE_MEN if index % 2 == 0 else STATURE_WOMEN
        stature = float(rng.normal(mean, sd))
        upper, fore = rng.normal(1.0, RATIO_SPREAD, size=2)
        subjects.append(
            Subject(
                f"S{index + 1:02d}",
                stature,
                float(UPPER_ARM_RATIO * stature * upper),
                float(FOREARM_RATIO * stature * fore),
            )
        )
    return subjects
