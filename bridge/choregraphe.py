"""Choregraphe behavior files (``.xar``): write command frames, read keys back.

The file is what Choregraphe 2.x saves as a project's ``behavior.xar``
(``xar_version="3"``): a root box whose diagram holds two boxes, run one
after the other:

1. a Python script box (``bridge.start_box``), started by the root's
   ``onStart``, that moves the arm to the trajectory's start posture within
   20 % of its limits (``ALMotion.angleInterpolation`` of minimum-jerk keys,
   ``bridge.script_approach``), so
   the behavior may be played from any posture, then fires ``onStopped``;
2. a *Timeline* box, started by it and ending the root through its
   ``onStopped``. Its ``Timeline`` element (``fps``, ``start_frame="1"``,
   ``size`` = last frame) has an ``ActuatorList`` of one ``ActuatorCurve``
   per joint, each a list of ``<Key frame="k" value="v">``: ``v`` in
   degrees (``unit="0"``), or the open fraction 0..1 for a hand
   (``unit="1"``), holding its two ``<Tangent side="left"|"right"
   interpType="bezier" abscissaParam="x" ordinateParam="y" />``: the
   handles' offsets in frames and in the curve's unit, a third of the way
   to the neighbouring keys, their slope the trajectory's velocity there
   (``bridge.key_tangents``), so that the runtime plays the planned curve.

Choregraphe's runtime plays a key at frame ``k`` ``(k - start_frame) /
fps`` seconds after the timeline starts; the keys are the start posture at
frame 1 (0 s), command frame ``k`` at frame ``k + 1`` (``k / fps``, the
frames' own time base), and the last posture held a little longer
(``bridge.timeline_keys``). Sources: Aldebaran's timeline runtime
(libqicore-compat ``timeline.cpp``, ``ActuatorCurve`` and ``Key`` models:
``actuator``, ``unit`` 0 degrees / 1 "percent", which the runtime sends
unscaled, so a hand's key is its open fraction 0..1 as ALMotion takes it,
``Key`` ``frame``/``value`` with 0 or 2 ``Tangent`` elements, ``fps`` an
int) and behavior files saved by Choregraphe 2.1-2.8; see ``docs/robot.md``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import NamedTuple
from xml.sax.saxutils import quoteattr

import numpy as np
import numpy.typing as npt

from bridge.bezier_auto import auto_handles
from bridge.start_box import start_script
from bridge.timeline_keys import (
    DECIMALS,
    QUANTUM,
    START_FRAME,
    TANGENT_DECIMALS,
    TimelineKeys,
    behavior_frames,
    is_hand,
    timeline_fps,
    timeline_keys,
)
from shared.errors import InvalidInputError
from shared.messages import CommandFrames
from shared.output_paths import write_output_text
from shared.text.counted import counted

__all__ = [
    "DECIMALS",
    "NAMESPACE",
    "QUANTUM",
    "TimelineKeys",
    "behavior_frames",
    "behavior_xml",
    "read_behavior",
    "timeline_fps",
    "timeline_from_xml",
    "write_behavior",
]

#: XML namespace of Choregraphe projects.
NAMESPACE = "http://www.aldebaran-robotics.com/schema/choregraphe/project.xsd"
#: Curve units of Choregraphe: degrees for joints, a fraction for hands.
DEGREE_UNIT, FRACTION_UNIT = 0, 1
#: Box ids in the root's diagram (the root itself is 0 in its links).
START_BOX, TIMELINE_BOX = 1, 2

_PORTS = (
    ("Input", "onLoad", 0, 1, "Signal sent when diagram is loaded."),
    ("Input", "onStart", 2, 0, "Box behavior starts when a signal is received."),
    ("Input", "onStop", 3, 0, "Box behavior stops when a signal is received."),
    ("Output", "onStopped", 1, 0, "Signal sent when box behavior is finished."),
)
#: Port ids of every box: ``onStart`` (an input) and ``onStopped`` (an output).
ON_START, ON_STOPPED = 2, 4
#: Bitmaps of the boxes, as Choregraphe's own.
_BITMAPS = {
    "root": "media/images/box/root.png",
    "script": "media/images/box/box-python-script.png",
    "timeline": "media/images/box/movement/move.png",
}


def _ports(indent: str) -> str:
    return "\n".join(
        f'{indent}<{tag} name="{name}" type="1" type_size="1" nature="{nature}" '
        f'inner="{inner}" tooltip={quoteattr(tip)} id="{i}" />'
        for i, (tag, name, nature, inner, tip) in enumerate(_PORTS, start=1)
    )


def _box_head(
    name: str,
    box_id: int,
    kind: str,
    tooltip: str,
    xy: str,
    indent: str,
    script: str = "",
) -> str:
    """A box's opening: name, bitmap, script (Python, in CDATA) and ports."""
    inner = indent + "    "
    return (
        f'{indent}<Box name={quoteattr(name)} id="{box_id}" localization="8" '
        f"tooltip={quoteattr(tooltip)} {xy}>\n"
        f"{inner}<bitmap>{_BITMAPS[kind]}</bitmap>\n"
        f'{inner}<script language="4">\n{inner}    <content>\n'
        f"{inner}        <![CDATA[{script}]]>\n"
        f"{inner}    </content>\n{inner}</script>\n"
        f"{_ports(inner)}\n"
    )


def _curve(name: str, keys: TimelineKeys, j: int, ind: str) -> str:
    """Curve ``j`` of ``keys``: its ``ActuatorCurve`` and ``Key`` elements."""
    unit = FRACTION_UNIT if is_hand(name) else DEGREE_UNIT
    numbers, values = keys.frames[j].tolist(), keys.values[j].tolist()
    if keys.left is None or keys.right is None:
        body = "".join(
            f'{ind}    <Key frame="{k}" value="{v:.{DECIMALS}f}" />\n'
            for k, v in zip(numbers, values, strict=True)
        )
    else:
        body = "".join(
            f'{ind}    <Key frame="{k}" value="{v:.{DECIMALS}f}">\n'
            f"{_tangent('left', left, ind + '        ')}"
            f"{_tangent('right', right, ind + '        ')}"
            f"{ind}    </Key>\n"
            for k, v, left, right in zip(
                numbers, values, keys.left[j], keys.right[j], strict=True
            )
        )
    return (
        f'{ind}<ActuatorCurve name="value" actuator={quoteattr(name)} '
        f'recordable="1" mute="0" unit="{unit}">\n{body}{ind}</ActuatorCurve>\n'
    )


def _tangent(side: str, handle: np.ndarray, ind: str) -> str:
    """A key's ``Tangent``: its handle's offset in frames and in the curve's unit."""
    x, y = (f"{float(v):.{TANGENT_DECIMALS}f}" for v in handle)
    return (
        f'{ind}<Tangent side="{side}" interpType="bezier" '
        f'abscissaParam="{x}" ordinateParam="{y}" />\n'
    )


def _start_box(keys: TimelineKeys, indent: str) -> str:
    """The script box that brings the arm to the first key (``bridge.start_box``)."""
    timeline = [keys.angles(name).tolist() for name in keys.names]
    times = [keys.times(name).tolist() for name in keys.names]
    tip = "Moves the arm to the trajectory's start at 20 % of its speed limits."
    return (
        _box_head(
            "Go to start",
            START_BOX,
            "script",
            tip,
            'x="80" y="60"',
            indent,
            start_script(keys.names, timeline, times),
        )
        + f"{indent}</Box>\n"
    )


def _timeline_box(keys: TimelineKeys, tip: str, name: str, indent: str) -> str:
    inner = indent + "    "
    curves = "".join(
        _curve(joint, keys, j, inner + "        ") for j, joint in enumerate(keys.names)
    )
    return (
        _box_head(name, TIMELINE_BOX, "timeline", tip, 'x="260" y="60"', indent)
        + f'{inner}<Timeline enable="1" fps="{keys.fps}" '
        f'start_frame="{keys.start_frame}" end_frame="-1" '
        f'size="{int(keys.frames[0][-1])}">\n'
        f'{inner}    <ActuatorList model="">\n{curves}'
        f"{inner}    </ActuatorList>\n{inner}</Timeline>\n{indent}</Box>\n"
    )


def _link(to_box: int, to_port: int, from_box: int, from_port: int) -> str:
    return (
        f'<Link inputowner="{to_box}" indexofinput="{to_port}" '
        f'outputowner="{from_box}" indexofoutput="{from_port}" />\n'
    )


def _check_frame_numbers(frames: CommandFrames) -> None:
    """Every frame must sit on a whole frame of the timeline."""
    for i, t in enumerate(frames.times):
        if not math.isclose(t * frames.rate, round(t * frames.rate), abs_tol=1e-6):
            raise InvalidInputError(
                f"frame {i + 1} at t = {t:.6f} s is not on a frame of a "
                f"{frames.rate:g} fps timeline",
                field="times",
            )


def behavior_xml(
    frames: CommandFrames,
    *,
    velocities: npt.ArrayLike,
    name: str = "armplan trajectory",
) -> str:
    """The Choregraphe behavior (``behavior.xar`` text) that replays ``frames``.

    Args:
        frames: Command frames on whole frames of their timeline [s, rad],
            at a whole number of frames per second.
        velocities: The trajectory's velocities at frame 0 and each frame
            [rad/s; /s for a hand], shape (m + 1, n)
            (``bridge.frames.frame_velocities``): the keys' tangents.
        name: Name of the timeline box shown in Choregraphe.

    Raises:
        InvalidInputError: the rate is not a whole number (``timeline_fps``),
            a frame is not on a frame of the timeline, or ``velocities`` is
            not one row per key.
    """
    timeline_fps(frames.rate)
    _check_frame_numbers(frames)
    keys = timeline_keys(frames, velocities)
    tip = (
        f"{frames.arm.value} arm trajectory from armplan: "
        f"{counted(len(frames.times), 'frame')}"
    )
    d = "    "
    return (
        '<?xml version="1.0" encoding="UTF-8" ?>\n'
        f'<ChoregrapheProject xmlns="{NAMESPACE}" xar_version="3">\n'
        + _box_head("root", -1, "root", "Root box of the behavior.", 'x="0" y="0"', d)
        + f'{d * 2}<Timeline enable="0">\n'
        f'{d * 3}<BehaviorLayer name="behavior_layer1">\n'
        f'{d * 4}<BehaviorKeyframe name="keyframe1" index="1">\n'
        f"{d * 5}<Diagram>\n"
        + _start_box(keys, d * 6)
        + _timeline_box(keys, tip, name, d * 6)
        + d * 6
        + _link(START_BOX, ON_START, 0, ON_START)
        + d * 6
        + _link(TIMELINE_BOX, ON_START, START_BOX, ON_STOPPED)
        + d * 6
        + _link(0, ON_STOPPED, TIMELINE_BOX, ON_STOPPED)
        + f"{d * 5}</Diagram>\n{d * 4}</BehaviorKeyframe>\n"
        f"{d * 3}</BehaviorLayer>\n{d * 2}</Timeline>\n{d}</Box>\n"
        "</ChoregrapheProject>\n"
    )


def write_behavior(
    frames: CommandFrames, path: str | Path, *, velocities: npt.ArrayLike
) -> Path:
    """Write ``frames`` as a Choregraphe behavior file; returns its path.

    ``velocities`` as :func:`behavior_xml` takes them. Whole or not at all
    (``shared.output_paths.write_output_text``): a write that fails part-way
    leaves an older file of that name as it was.

    Raises:
        InvalidInputError: naming the path and the reason it cannot be
            written, or what :func:`behavior_xml` refuses.
    """
    return write_output_text(path, behavior_xml(frames, velocities=velocities))


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


class _CurveKeys(NamedTuple):
    """One ``ActuatorCurve``'s keys as read, by frame (see ``TimelineKeys``)."""

    numbers: np.ndarray
    values: np.ndarray
    left: np.ndarray
    right: np.ndarray


def _curve_keys(curve: ET.Element) -> _CurveKeys:
    """A curve's keys and their tangents; keys without any get BezierAuto ones."""
    name = curve.attrib.get("actuator", "?")
    rows = []
    for key in (e for e in curve if _local(e.tag) == "Key"):
        try:
            frame, value = int(key.attrib["frame"]), float(key.attrib["value"])
        except (KeyError, ValueError) as exc:
            raise InvalidInputError(
                f"Choregraphe key of {name} without a valid frame or value: {exc}",
                field="Key",
            ) from None
        rows.append((frame, value, _key_tangents(key, name, frame)))
    rows.sort(key=lambda row: row[0])
    numbers = np.array([r[0] for r in rows], dtype=int)
    values = np.array([r[1] for r in rows], dtype=float)
    auto_left, auto_right = auto_handles(numbers, values[:, None])
    left, right = auto_left[:, 0].copy(), auto_right[:, 0].copy()
    for i, (_, _, written) in enumerate(rows):
        if written is not None:
            left[i], right[i] = written
    return _CurveKeys(numbers, values, left, right)


def _key_tangents(
    key: ET.Element, name: str, frame: int
) -> tuple[np.ndarray, np.ndarray] | None:
    """A key's left and right handles (abscissa, ordinate) as written, or None.

    As the runtime reads them (libqicore-compat ``KeyModel``,
    ``TangentModel``): none, or two, one a side; only Bezier ones here.
    """
    tangents = [e for e in key if _local(e.tag) == "Tangent"]
    if not tangents:
        return None
    where = f"{name}'s key at frame {frame}"
    sides = sorted(t.attrib.get("side", "") for t in tangents)
    if sides != ["left", "right"]:
        raise InvalidInputError(
            f"{where} has tangents {sides}: a key has none, or one left and one right",
            field="Tangent",
        )
    handles = {}
    for tangent in tangents:
        kind = tangent.attrib.get("interpType")
        if kind != "bezier":
            raise InvalidInputError(
                f"{where} has a {kind!r} tangent: armplan reads Bezier tangents only",
                field="Tangent",
            )
        try:
            handle = [
                float(tangent.attrib[a]) for a in ("abscissaParam", "ordinateParam")
            ]
        except (KeyError, ValueError) as exc:
            raise InvalidInputError(
                f"{where} has a tangent without a valid abscissa or ordinate: {exc}",
                field="Tangent",
            ) from None
        handles[tangent.attrib["side"]] = np.array(handle)
    return handles["left"], handles["right"]


def _keyed_timeline(root: ET.Element) -> ET.Element:
    for element in root.iter():
        if _local(element.tag) == "Timeline" and any(
            _local(e.tag) == "ActuatorList" for e in element
        ):
            return element
    raise InvalidInputError(
        "no Timeline with an ActuatorList in this behavior", field="Timeline"
    )


def _whole(timeline: ET.Element, attribute: str, default: str) -> int:
    """A timeline's whole-number attribute, read as the runtime reads it: an int."""
    text = timeline.attrib.get(attribute, default)
    try:
        return int(text)
    except ValueError:
        raise InvalidInputError(
            f"timeline {attribute} {text!r} is not a whole number: Choregraphe's "
            "runtime reads it as an int",
            field=attribute,
        ) from None


def timeline_from_xml(text: str) -> TimelineKeys:
    """The keys of the first keyed timeline in a behavior's XML text.

    ``fps`` and ``start_frame`` are read as the runtime reads them, as whole
    numbers (``start_frame`` 1 if absent, as Choregraphe writes it); each
    key's tangents too, as written, or for a key without any the runtime's
    BezierAuto ones (``bridge.bezier_auto``).

    Raises:
        InvalidInputError: not XML, no keyed timeline, ``fps`` or
            ``start_frame`` not a whole number, a key without a frame or
            value, or a key whose tangents are not one left and one right
            Bezier tangent with an abscissa and an ordinate.
    """
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise InvalidInputError(f"not a Choregraphe behavior: {exc}") from None
    timeline = _keyed_timeline(root)
    fps = _whole(timeline, "fps", "25")
    start = _whole(timeline, "start_frame", str(START_FRAME))
    names, curves = [], []
    for curve in timeline.iter():
        if _local(curve.tag) == "ActuatorCurve":
            curves.append(_curve_keys(curve))
            names.append(curve.attrib["actuator"])
    return TimelineKeys(
        fps,
        names,
        [c.numbers for c in curves],
        [c.values for c in curves],
        start,
        [c.left for c in curves],
        [c.right for c in curves],
    )


def read_behavior(path: str | Path) -> TimelineKeys:
    """The keys of a Choregraphe behavior file."""
    return timeline_from_xml(Path(path).read_text(encoding="utf-8"))
