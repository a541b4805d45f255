"""Notes on a capture whose arm does not move as a demonstration's does.

A marker map's ``axes`` turn the lab's axes into the subject's torso axes
(forward, left, up). A rotation that is the wrong one (the lab's up taken
for down, say) passes every check of the map (it is a rotation, not a
mirror) and imports without a word: the segments keep their lengths, and
only the fit's gravity term and the goals come out wrong. Demonstrations
start with the arm hanging and reach a goal in front of the body (the
paper's protocol, and the synthetic set's); a capture whose elbow starts
above the shoulder, or whose reach ends behind it, more likely has the
wrong axes than such a movement, so the import says so. A note, not an
error: a lab may record other movements on purpose.
"""

from __future__ import annotations

from shared.demos.retarget import ArmTrack

#: How far above the shoulder an elbow may start without a note [m].
ELBOW_ABOVE = 0.05
#: How far behind the shoulder a reach may end without a note [m].
WRIST_BEHIND = 0.05


def posture_notes(human: ArmTrack) -> list[str]:
    """What looks unlike a demonstration in ``human``'s positions (torso axes).

    Args:
        human: The subject's arm [m] in torso axes (forward, left, up), each
            shape (n, 3).

    Returns:
        Notes for the import to report (empty: nothing odd).
    """
    notes = []
    above = float(human.elbow[0, 2] - human.shoulder[0, 2])
    if above > ELBOW_ABOVE:
        notes.append(
            f"the elbow starts {above:.2f} m above the shoulder, where a "
            "demonstration starts with the arm hanging: is the marker map's "
            "third axis the lab's up?"
        )
    behind = float(human.shoulder[-1, 0] - human.wrist[-1, 0])
    if behind > WRIST_BEHIND:
        notes.append(
            f"the reach ends {behind:.2f} m behind the shoulder, where a "
            "demonstration reaches a goal in front of the body: is the marker "
            "map's first axis the subject's forward?"
        )
    return notes
