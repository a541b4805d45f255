"""Trajectories to NAO command frames, and to the robot over NAOqi (libqi).

- :mod:`bridge.frames`: a trajectory as command frames at a timeline's rate.
- :mod:`bridge.choregraphe`, :mod:`bridge.python_export`,
  :mod:`bridge.almotion`: the frames as a Choregraphe behavior (its
  timeline's keys: :mod:`bridge.timeline_keys`, their tangents:
  :mod:`bridge.key_tangents`, the curve they play: :mod:`bridge.bezier_curve`;
  its box to the start: :mod:`bridge.start_box`), a Choregraphe-style Python
  script, and an ALMotion ``angleInterpolation`` call.
- :mod:`bridge.velocity_agreement`, :mod:`bridge.checks`,
  :mod:`bridge.fidelity`: the trajectory's velocities against its positions,
  every frame against the joints' limits, and the lines between frames
  against the trajectory, before anything is sent (all:
  :mod:`bridge.checked_frames`).
- :mod:`bridge.naoqi_client`, :mod:`bridge.playback`,
  :mod:`bridge.robot_bridge`, :mod:`bridge.tracking`: sending to a NAO,
  reading back, and the tracking report; :mod:`bridge.stopper`: stopping
  the arm of a robot given up on until its call has ended.
- :mod:`bridge.sim`: the simulated NAO, a separate process.

``shared.libqi`` is imported first: libqi must load before pinocchio.
"""

import shared.libqi  # noqa: F401  (first: see shared/libqi.py)
from bridge.almotion import AngleInterpolationCall, angle_interpolation_call
from bridge.checked_frames import check_behavior, checked_frames
from bridge.checks import check_frames
from bridge.choregraphe import behavior_xml, read_behavior, write_behavior
from bridge.frames import (
    DEFAULT_RATE,
    frame_times,
    frame_velocities,
    frames_from_trajectory,
)
from bridge.limits import FrameLimits
from bridge.naoqi_client import NaoqiClient
from bridge.python_export import python_script, write_python
from bridge.robot_bridge import RobotBridge

__all__ = [
    "DEFAULT_RATE",
    "AngleInterpolationCall",
    "FrameLimits",
    "NaoqiClient",
    "RobotBridge",
    "angle_interpolation_call",
    "behavior_xml",
    "check_behavior",
    "check_frames",
    "checked_frames",
    "frame_times",
    "frame_velocities",
    "frames_from_trajectory",
    "python_script",
    "read_behavior",
    "write_behavior",
    "write_python",
]
