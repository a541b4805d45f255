"""Command frames as NAOqi holds them: angles and times as 32-bit floats.

ALMotion takes ``angleInterpolation``'s angles and times as ``ALValue``
floats, and Choregraphe's runtime holds a key's value as a C ``float``
(``KeyModel``: ``float _value``) and sends ``value * TO_RAD`` and ``float(frame
- start_frame) / fps``, computed in floats. Rounded to 32 bits, a time near
4 s moves by up to 2.4e-7 s, which at 900 fps (1.1 ms between frames) made
the demo's trajectory break the jerk limit by 10 % though its 64-bit frames
passed. The checks (``bridge.checks.check_frames``) therefore run on the
frames as held, too; and the frames are held inside the joints' ranges by
``RANGE_INSET``, so that no rounding on the way puts an angle outside.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shared.messages import CommandFrames

#: How far inside its joint's range every frame is held [rad]: four 32-bit
#: steps at pi (above every joint's bound), beyond what the degree text
#: (1e-6 degree), its 32-bit value and the 32-bit product with TO_RAD round.
RANGE_INSET = 4.0 * float(np.spacing(np.float32(np.pi)))
#: ``TO_RAD`` as Choregraphe's runtime holds it (``AL::Math::TO_RAD``, a float).
TO_RAD = np.float32(np.pi / 180.0)


def held(values: npt.ArrayLike) -> np.ndarray:
    """``values`` rounded to 32-bit floats, back as 64-bit ones (same shape)."""
    return np.asarray(values, dtype=np.float32).astype(float)


def as_held(frames: CommandFrames) -> CommandFrames:
    """``frames`` with every angle and time rounded to 32 bits, as NAOqi holds them."""
    return frames.model_copy(
        update={
            "start": held(frames.start).tolist(),
            "times": held(frames.times).tolist(),
            "positions": held(frames.positions).tolist(),
        }
    )


def degrees_as_radians(degrees: npt.ArrayLike) -> np.ndarray:
    """Degrees as Choregraphe's runtime turns them into radians, in 32 bits."""
    return (np.asarray(degrees, dtype=np.float32) * TO_RAD).astype(float)


def frame_times(frames: npt.ArrayLike, fps: int) -> np.ndarray:
    """``frames / fps`` [s] as the runtime computes it: a 32-bit division."""
    return (np.asarray(frames, dtype=np.float32) / np.float32(fps)).astype(float)
