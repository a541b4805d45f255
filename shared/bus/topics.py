"""Every topic armplan publishes, relative to the namespace, with its message.

Zenoh subscribers see publications only (not queries), so each stage of a
planning session is also *published*: the planner puts the request it got,
the decision, the joint path and the trajectory; the bridge puts the command
frames, each measured joint state, the tracking report and each
execution's outcome; the fit service
puts each new model. The recorder subscribes to these topics and gives each
one an MCAP channel whose JSON schema is its message class's; a topic not
listed here (or a payload that does not parse as its class) is recorded on a
schemaless channel (schema name ``"json"``).

With the default namespace ``armplan`` the trajectory topic is
``armplan/plan/trajectory``.
"""

from __future__ import annotations

from dataclasses import dataclass

from shared.bus.keys import check_path
from shared.bus.routes import MODEL_TOPIC, TRAJECTORY_TOPIC
from shared.messages import (
    Decision,
    JointPath,
    Message,
    MotionModel,
    PlanRequest,
    Trajectory,
)
from shared.messages.frames import (
    CommandFrames,
    ExecutionOutcome,
    JointState,
    TrackingReport,
)

#: Each request the planner accepts (``PlanRequest``).
PLAN_REQUEST_TOPIC = "plan/request"
#: The motion decision of each plan (``Decision``).
DECISION_TOPIC = "plan/decision"
#: The joint path from IK, before timing (``JointPath``).
JOINT_PATH_TOPIC = "plan/joint_path"
#: The command frames the bridge sends to the robot (``CommandFrames``).
BRIDGE_FRAMES_TOPIC = "bridge/frames"
#: Each measured joint state while the robot moves (``JointState``).
BRIDGE_STATE_TOPIC = "bridge/state"
#: The tracking report after each execution (``TrackingReport``).
BRIDGE_REPORT_TOPIC = "bridge/report"
#: How each execution ended: completed, stopped or an error (``ExecutionOutcome``).
BRIDGE_OUTCOME_TOPIC = "bridge/outcome"


@dataclass(frozen=True)
class Topic:
    """One published topic.

    Attributes:
        path: The key under the namespace, e.g. ``"plan/trajectory"``.
        message: The message class of its payloads (its JSON schema is the
            channel's), or ``None`` while the class is not in ``shared/``.
        publisher: The process that publishes it, e.g. ``"planner"``.
        droppable: Whether a publication may be dropped when the link is
            congested (Zenoh's ``DROP``): only a stream whose next sample
            soon replaces the last (``bridge/state``, 50 Hz), so its
            publisher never waits. Every other topic is put with ``BLOCK``:
            a burst waits for room rather than losing a trajectory the
            follower should play or the recorder keep (with ``DROP``, 40
            trajectories of 5 MB put at once to a busy subscriber arrived
            35).
    """

    path: str
    message: type[Message] | None
    publisher: str
    droppable: bool = False

    def __post_init__(self) -> None:
        check_path(self.path, "topic")

    def key(self, namespace: str) -> str:
        """The full key, e.g. ``armplan/plan/trajectory``."""
        return f"{namespace}/{self.path}"


#: Every published topic, in the order a session produces them.
TOPICS: tuple[Topic, ...] = (
    Topic(PLAN_REQUEST_TOPIC, PlanRequest, "planner"),
    Topic(DECISION_TOPIC, Decision, "planner"),
    Topic(JOINT_PATH_TOPIC, JointPath, "planner"),
    Topic(TRAJECTORY_TOPIC, Trajectory, "planner"),
    Topic(BRIDGE_FRAMES_TOPIC, CommandFrames, "bridge"),
    Topic(BRIDGE_STATE_TOPIC, JointState, "bridge", droppable=True),
    Topic(BRIDGE_REPORT_TOPIC, TrackingReport, "bridge"),
    Topic(BRIDGE_OUTCOME_TOPIC, ExecutionOutcome, "bridge"),
    Topic(MODEL_TOPIC, MotionModel, "fit"),
)

_BY_PATH = {topic.path: topic for topic in TOPICS}


def topic_paths() -> tuple[str, ...]:
    """The path of every registered topic, e.g. ``("plan/request", ...)``."""
    return tuple(topic.path for topic in TOPICS)


def find_topic(path: str) -> Topic | None:
    """The registered topic at ``path`` (relative to the namespace), if any."""
    return _BY_PATH.get(path)


def droppable(path: str) -> bool:
    """Whether publications on ``path`` may be dropped under congestion.

    False for an unregistered path: what is not known to be replaced soon
    is kept.
    """
    topic = _BY_PATH.get(path)
    return topic is not None and topic.droppable


def topic_message(path: str) -> type[Message] | None:
    """The message class of the topic at ``path``; ``None`` if unknown or unset."""
    topic = _BY_PATH.get(path)
    return None if topic is None else topic.message
