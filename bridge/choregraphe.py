"""Choregraphe behavior files (``.xar``): write command frames, read keys back.

The file is what Choregraphe 2.x saves as a project's ``behavior.xar``
(``xar_version="3"``): a root box whose diagram holds one *Timeline* box,
started by the root's ``onStart`` and ending it through ``onStopped``. The
timeline box has a ``Timeline`` element (``fps``, ``start_frame="1"``,
``size`` = last frame) with an ``ActuatorList`` of one ``ActuatorCurve`` per
joint, each a list of ``<Key frame="k" value="v" />``: ``v`` in degrees
(``unit="0"``), or the open fraction 0..1 for a hand (``unit="1"``).
Choregraphe's runtime reads a key at frame ``k`` as reached ``k / fps``
seconds after the timeline starts (its Python export writes the same times),
which is the frames' own time base. Sources: Aldebaran's timeline runtime
(``ActuatorCurve::loadFromXml``: ``actuator``, ``unit`` 0 degrees / 1
percent, ``Key`` ``frame``/``value``) and behavior files saved by
Choregraphe 2.1-2.8; see ``docs/robot.md``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import NamedTuple
from xml.sax.saxutils import quoteattr

import numpy as np

from shared.errors import InvalidInputError
from shared.messages import CommandFrames
from shared.output_paths import write_output_text

#: XML namespace of Choregraphe projects.
NAMESPACE = "http://www.aldebaran-robotics.com/schema/choregraphe/project.xsd"
#: Curve units of Choregraphe: degrees for joints, a fraction for hands.
DEGREE_UNIT, FRACTION_UNIT = 0, 1
#: Decimals written for each key's value (1e-6 degree: rounding to 1e-4
#: degree alone made a 1000 fps timeline's jerk 3.6 times the bridge's limit).
DECIMALS = 6
#: The smallest step of a written angle [rad]: frames are held this far
#: inside the joints' ranges, so that rounding never puts one outside.
QUANTUM = math.radians(10.0**-DECIMALS)

_PORTS = (
    ("Input", "onLoad", 0, 1, "Signal sent when diagram is loaded."),
    ("Input", "onStart", 2, 0, "Box behavior starts when a signal is received."),
    ("Input", "onStop", 3, 0, "Box behavior stops when a signal is received."),
    ("Output", "onStopped", 1, 0, "Signal sent when box behavior is finished."),
)


class TimelineKeys(NamedTuple):
    """The keys of a Choregraphe timeline.

    Attributes:
        fps: Frame rate of the timeline [Hz], a whole number as the runtime
            reads it.
        names: Actuators in file order, shape (n,).
        frames: Frame numbers of each actuator's keys, n arrays of shape (m_i,).
        values: Values of those keys as written (degrees, or fraction for a
            hand), n arrays of shape (m_i,).
    """

    fps: int
    names: list[str]
    frames: list[np.ndarray]
    values: list[np.ndarray]

    def times(self, name: str) -> np.ndarray:
        """Times of ``name``'s keys from the timeline's start [s], shape (m,)."""
        return self.frames[self.names.index(name)] / self.fps

    def angles(self, name: str) -> np.ndarray:
        """``name``'s keys in SI: radians for a joint, fraction for a hand."""
        values = self.values[self.names.index(name)]
        return values if _is_hand(name) else np.radians(values)


def _is_hand(name: str) -> bool:
    return name.endswith("Hand")


def _ports(indent: str) -> str:
    return "\n".join(
        f'{indent}<{tag} name="{name}" type="1" type_size="1" nature="{nature}" '
        f'inner="{inner}" tooltip={quoteattr(tip)} id="{i}" />'
        for i, (tag, name, nature, inner, tip) in enumerate(_PORTS, start=1)
    )


def _box_head(name: str, box_id: int, tooltip: str, xy: str, indent: str) -> str:
    inner = indent + "    "
    return (
        f'{indent}<Box name={quoteattr(name)} id="{box_id}" localization="8" '
        f"tooltip={quoteattr(tooltip)} {xy}>\n"
        f"{inner}<bitmap>media/images/box/"
        f"{'root' if box_id < 0 else 'movement/move'}.png</bitmap>\n"
        f'{inner}<script language="4">\n{inner}    <content>\n'
        f"{inner}        <![CDATA[]]>\n{inner}    </content>\n{inner}</script>\n"
        f"{_ports(inner)}\n"
    )


def _shown(name: str, values: np.ndarray) -> list[str]:
    """A curve's values as the file holds them: degrees (fraction for a hand)."""
    shown = values if _is_hand(name) else np.degrees(values)
    return [f"{v:.{DECIMALS}f}" for v in shown]


def behavior_frames(frames: CommandFrames) -> CommandFrames:
    """``frames`` as the behavior file holds them: each value rounded as written.

    This is what Choregraphe plays, so it is what the bridge's checks must
    pass (``armplan export`` and the demo check it).
    """
    positions = np.asarray(frames.positions, dtype=float)
    written = np.column_stack(
        [
            np.array(_shown(name, positions[:, j]), dtype=float)
            for j, name in enumerate(frames.joint_names)
        ]
    )
    hands = np.array([_is_hand(name) for name in frames.joint_names])
    read = np.where(hands, written, np.radians(written))
    return frames.model_copy(update={"positions": read.tolist()})


def _curve(name: str, frame_numbers: list[int], values: np.ndarray, ind: str) -> str:
    unit = FRACTION_UNIT if _is_hand(name) else DEGREE_UNIT
    keys = "".join(
        f'{ind}    <Key frame="{k}" value="{v}" />\n'
        for k, v in zip(frame_numbers, _shown(name, values), strict=True)
    )
    return (
        f'{ind}<ActuatorCurve name="value" actuator={quoteattr(name)} '
        f'recordable="1" mute="0" unit="{unit}">\n{keys}{ind}</ActuatorCurve>\n'
    )


def timeline_fps(rate: float, what: str = "the frame rate") -> int:
    """``rate`` [Hz] as a Choregraphe timeline's ``fps``: a whole number.

    Choregraphe's runtime holds a timeline's fps as an ``int``
    (libqicore-compat ``AnimationModel``: ``int _fps`` read by
    ``getAttribute("fps", _fps)``; ``Timeline::setFPS(int)``; a frame every
    ``1000 / fps`` ms): ``fps="12.5"`` would not play at the times checked
    (read as 12, or not at all and the default used). The Python export
    keeps any rate.

    Args:
        rate: The frame rate asked for [Hz].
        what: How the message names it (``--rate`` for the command line).

    Raises:
        InvalidInputError: ``rate`` is not a whole number, shown as given.
    """
    rate = float(rate)
    if rate.is_integer():
        return int(rate)
    near = (
        f": use {max(1, math.floor(rate))} or {math.ceil(rate)} fps"
        if math.isfinite(rate)
        else ""
    )
    raise InvalidInputError(
        f"{what} of a Choregraphe behavior must be a whole number of frames "
        f"per second (its runtime holds fps as an int), got {rate!r}{near}, "
        "or export python, which keeps any rate",
        field="rate",
        rate=rate,
    )


def _timeline_box(frames: CommandFrames, name: str, indent: str) -> str:
    fps = timeline_fps(frames.rate)
    numbers = frames.frame_numbers
    positions = np.asarray(frames.positions)
    inner = indent + "    "
    curves = "".join(
        _curve(joint, numbers, positions[:, j], inner + "        ")
        for j, joint in enumerate(frames.joint_names)
    )
    tip = f"{frames.arm.value} arm trajectory from armplan: {len(numbers)} frames"
    return (
        _box_head(name, 1, tip, 'x="200" y="60"', indent)
        + f'{inner}<Timeline enable="1" fps="{fps}" start_frame="1" '
        f'end_frame="-1" size="{numbers[-1]}">\n'
        f'{inner}    <ActuatorList model="">\n{curves}'
        f"{inner}    </ActuatorList>\n{inner}</Timeline>\n{indent}</Box>\n"
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


def behavior_xml(frames: CommandFrames, name: str = "armplan trajectory") -> str:
    """The Choregraphe behavior (``behavior.xar`` text) that replays ``frames``.

    Args:
        frames: Command frames on whole frames of their timeline [s, rad],
            at a whole number of frames per second.
        name: Name of the timeline box shown in Choregraphe.

    Raises:
        InvalidInputError: the rate is not a whole number (``timeline_fps``),
            or a frame is not on a frame of the timeline.
    """
    timeline_fps(frames.rate)
    _check_frame_numbers(frames)
    d = "    "
    return (
        '<?xml version="1.0" encoding="UTF-8" ?>\n'
        f'<ChoregrapheProject xmlns="{NAMESPACE}" xar_version="3">\n'
        + _box_head("root", -1, "Root box of the behavior.", 'x="0" y="0"', d)
        + f'{d * 2}<Timeline enable="0">\n'
        f'{d * 3}<BehaviorLayer name="behavior_layer1">\n'
        f'{d * 4}<BehaviorKeyframe name="keyframe1" index="1">\n'
        f"{d * 5}<Diagram>\n"
        + _timeline_box(frames, name, d * 6)
        + f'{d * 6}<Link inputowner="1" indexofinput="2" outputowner="0" '
        'indexofoutput="2" />\n'
        f'{d * 6}<Link inputowner="0" indexofinput="4" outputowner="1" '
        'indexofoutput="4" />\n'
        f"{d * 5}</Diagram>\n{d * 4}</BehaviorKeyframe>\n"
        f"{d * 3}</BehaviorLayer>\n{d * 2}</Timeline>\n{d}</Box>\n"
        "</ChoregrapheProject>\n"
    )


def write_behavior(frames: CommandFrames, path: str | Path) -> Path:
    """Write ``frames`` as a Choregraphe behavior file; returns its path.

    Raises:
        InvalidInputError: naming the path and the reason it cannot be written.
    """
    return write_output_text(path, behavior_xml(frames))


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _curve_keys(curve: ET.Element) -> tuple[np.ndarray, np.ndarray]:
    keys = [e for e in curve if _local(e.tag) == "Key"]
    try:
        pairs = sorted((int(k.attrib["frame"]), float(k.attrib["value"])) for k in keys)
    except (KeyError, ValueError) as exc:
        raise InvalidInputError(
            f"Choregraphe key without a valid frame or value: {exc}", field="Key"
        ) from None
    return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])


def _keyed_timeline(root: ET.Element) -> ET.Element:
    for element in root.iter():
        if _local(element.tag) == "Timeline" and any(
            _local(e.tag) == "ActuatorList" for e in element
        ):
            return element
    raise InvalidInputError(
        "no Timeline with an ActuatorList in this behavior", field="Timeline"
    )


def _whole_fps(text: str) -> int:
    """A timeline's ``fps`` attribute, read as the runtime reads it: an int."""
    try:
        return int(text)
    except ValueError:
        raise InvalidInputError(
            f"timeline fps {text!r} is not a whole number: Choregraphe's "
            "runtime reads it as an int",
            field="fps",
        ) from None


def timeline_from_xml(text: str) -> TimelineKeys:
    """The keys of the first keyed timeline in a behavior's XML text."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise InvalidInputError(f"not a Choregraphe behavior: {exc}") from None
    timeline = _keyed_timeline(root)
    fps = _whole_fps(timeline.attrib.get("fps", "25"))
    names, numbers, values = [], [], []
    for curve in timeline.iter():
        if _local(curve.tag) == "ActuatorCurve":
            k, v = _curve_keys(curve)
            names.append(curve.attrib["actuator"])
            numbers.append(k)
            values.append(v)
    return TimelineKeys(fps, names, numbers, values)


def read_behavior(path: str | Path) -> TimelineKeys:
    """The keys of a Choregraphe behavior file."""
    return timeline_from_xml(Path(path).read_text(encoding="utf-8"))
