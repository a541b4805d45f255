"""Every message armplan processes exchange, as pydantic models.

Each model gives the JSON wire format and the JSON schema of its MCAP channel.
"""

from shared.messages.base import Direction, JointVector, Message, Vec3, parse
from shared.messages.decision import Decision, PointDecision
from shared.messages.error import ErrorReply
from shared.messages.joint_path import JointPath, Trajectory
from shared.messages.kinematics import FKResult, IKRequest, IKResult
from shared.messages.method import Method
from shared.messages.target import PlanRequest, ReachTarget
from shared.messages.wrist_path import WristPath

__all__ = [
    "Decision",
    "Direction",
    "ErrorReply",
    "FKResult",
    "IKRequest",
    "IKResult",
    "JointPath",
    "JointVector",
    "Message",
    "Method",
    "PlanRequest",
    "PointDecision",
    "ReachTarget",
    "Trajectory",
    "Vec3",
    "WristPath",
    "parse",
]

# Command frames and what the robot did with them (the robot bridge).
from shared.messages.frames import (
    CommandFrames,
    ExecutedJointStates,
    ExecuteReply,
    ExecuteRequest,
    ExecutionOutcome,
    JointState,
    TrackingReport,
)

__all__ += [
    "CommandFrames",
    "ExecuteReply",
    "ExecuteRequest",
    "ExecutedJointStates",
    "ExecutionOutcome",
    "JointState",
    "TrackingReport",
]

# Stopping the arm through the bridge (``bridge/stop``).
from shared.messages.stop import StopReply, StopRequest  # noqa: E402

__all__ += ["StopReply", "StopRequest"]

# Human demonstrations (demonstration MCAP files, shared/demos).
from shared.messages.demo import DemoSample, DemoSubject  # noqa: E402

__all__ += ["DemoSample", "DemoSubject"]

# The planner's stage requests (decide, ik path, timing services).
from shared.messages.stages import (  # noqa: E402
    DecideRequest,
    PathIKRequest,
    TimingRequest,
    TimingSegment,
)

__all__ += ["DecideRequest", "PathIKRequest", "TimingRequest", "TimingSegment"]

# Acceleration and jerk limits a plan or timing request may set.
from shared.messages.timing_limits import TimingLimits  # noqa: E402

__all__ += ["TimingLimits"]

# The motion model (fit service: served, published, read by decide).
from shared.messages.motion_model import (  # noqa: E402
    ArmLengths,
    MotionModel,
    VariableFit,
)

__all__ += ["ArmLengths", "MotionModel", "VariableFit"]

# A request to fit a new motion model (fit service).
from shared.messages.fit_request import FitRequest  # noqa: E402

__all__ += ["FitRequest"]

# What a service spent on a request (the Zenoh attachment of its replies).
from shared.messages.service_timing import ServiceTiming  # noqa: E402

__all__ += ["ServiceTiming"]

# How long a caller waits (the Zenoh attachment of its queries).
from shared.messages.caller_budget import CallerBudget  # noqa: E402

__all__ += ["CallerBudget"]

# The palm a posture reached against the direction asked (ik, planner).
from shared.messages.palm_reached import PalmReached  # noqa: E402

__all__ += ["PalmReached"]
