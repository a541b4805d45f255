"""Command frames as a Choregraphe-style "export to Python" script.

Choregraphe's timeline export writes three lists, appended to per joint::

    names = list()
    times = list()
    keys = list()

    names.append("RShoulderPitch")
    times.append([0.04, 0.08, ...])   # [s], frame / fps
    keys.append([1.2, 1.21, ...])     # [rad] (a hand, RHand: open fraction)

and then calls ``motion.angleInterpolation(names, keys, times, True)``. The
script written here has exactly that block, plus a runner
(``bridge.play_runner``) that works on Python 2 (NAOqi's ``naoqi`` module,
or ``qi``) and Python 3 (the ``qi`` package): connect to ALMotion
(``tcp://127.0.0.1:9559`` or the URL given, within ``--timeout``), refuse a
robot not awake, stiffen the joints where they are (a limp arm's command
first moved to where it hangs: ``bridge.script_stiffen``), move slowly to
the start posture (``angleInterpolation`` of minimum-jerk keys within 20 %
of the speed, acceleration and jerk limits: ``bridge.script_approach``),
then play, and print ``played N frames (D s) on URL``. A refusal prints
``play.py: error: ...`` and exits 1 (a malformed URL: 2);
Ctrl-C stops the arm where it is and exits 130.
"""

from __future__ import annotations

from pathlib import Path

from bridge.play_runner import runner_source
from bridge.script_stiffen import STIFFEN_SOURCE
from shared.messages import CommandFrames
from shared.output_paths import write_output_text
from shared.text.counted import counted

#: Fraction of the speed, acceleration and jerk limits used to reach the start.
START_SPEED = 0.2


def _numbers(values: list[float]) -> str:
    """``values`` exactly, in their shortest round-trip form.

    The script plays what was checked: times rounded to 1e-6 s made a 900
    fps script's jerk 2.8 times the bridge's limit.
    """
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def python_script(frames: CommandFrames) -> str:
    """The Python script that replays ``frames`` with ``angleInterpolation``."""
    columns = list(zip(*frames.positions, strict=True))
    lines = [
        "# Choregraphe simplified export in Python.",
        f"# Written by armplan: {frames.arm.value} arm, "
        f"{counted(len(frames.times), 'frame')} "
        f"at {frames.rate:g} fps, {frames.duration:.3f} s.",
        "# Angles in radians, times in seconds from the start posture.",
        "names = list()",
        "times = list()",
        "keys = list()",
        "",
    ]
    for j, name in enumerate(frames.joint_names):
        lines += [
            f'names.append("{name}")',
            f"times.append({_numbers(list(frames.times))})",
            f"keys.append({_numbers(list(columns[j]))})",
            "",
        ]
    lines.append(f"start = {_numbers(list(frames.start))}")
    runner = runner_source(
        frames.arm.value, len(frames.times), frames.rate, frames.duration, START_SPEED
    )
    return "\n".join(lines) + STIFFEN_SOURCE + runner


def write_python(frames: CommandFrames, path: str | Path) -> Path:
    """Write the replay script of ``frames`` to ``path``; returns the path.

    Whole or not at all (``shared.output_paths.write_output_text``): a write
    that fails part-way leaves an older file of that name as it was.

    Raises:
        InvalidInputError: naming the path and the reason it cannot be written.
    """
    return write_output_text(path, python_script(frames))
