"""Reading the arm settled after a stop: two measured readings that agree.

:func:`not_settled` says why a stop's reply may not call the arm still:
its measured angles did not settle within the wait, or the robot did not
answer in time (the reads run on a thread of their own).
"""

from __future__ import annotations

import threading

from bridge.at_rest import READ_GAP, until_still
from bridge.naoqi_client import NaoqiClient
from shared.errors import ArmplanError

#: Two measured readings ``READ_GAP`` apart that differ by no more than
#: this on every joint: the arm is still [rad] (0.06 deg: 1.3 deg/s).
SETTLED = 1e-3


def not_settled(client: NaoqiClient, names: list[str], wait: float) -> str:
    """Why ``names``' measured angles were not read settled within ``wait`` [s].

    "" if they were. The reads run on a thread of their own, so that a
    robot that does not answer (a call's timeout, a connection's) takes no
    more than ``wait`` from the reply.
    """
    result: list[str] = []

    def read() -> None:
        try:
            until_still(
                client,
                names,
                use_sensors=True,
                tolerance=SETTLED,
                wait=wait,
                gap=READ_GAP,
                moving="its measured angles did not settle after the stop",
            )
            result.append("")
        except ArmplanError as error:
            result.append(error.message)
        except Exception as error:  # a reply is owed whatever happens
            result.append(f"{type(error).__name__}: {error}")

    reader = threading.Thread(target=read, name="stop-settle", daemon=True)
    reader.start()
    reader.join(wait)
    if not result:
        return f"the robot's angles were not read settled within {wait:.2f} s"
    return result[0]
