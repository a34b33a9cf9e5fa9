"""Python client of the MCM, the motion controller of the P-Rob2 arm.

- :class:`Client`: the JSON/TCP protocol (port 18010), standard library only.
- :class:`ShmClient` (``pip install mcm[shm]``): shared memory through iceoryx2 0.10.0, for
  controllers on the robot computer that run at the cycle rate.

>>> import mcm
>>> c = mcm.Client("localhost")            # doctest: +SKIP
>>> c.hold().operating_mode                # doctest: +SKIP
'HOLD'
"""

from . import codes, encoding, layout, wire
from .codes import ErrorCode
from .errors import (
    CommandError,
    ConnectionLost,
    McmError,
    McmTimeout,
    OutcomeUnknown,
    ProtocolError,
    ShmUnavailable,
)
from .tcp import DEFAULT_HOST, DEFAULT_PORT, Client
from .types import (
    AxisInfo,
    AxisStates,
    CartesianState,
    CommandErrorEvent,
    Info,
    InverseKinematicsResult,
    MoveAllResult,
    PayloadResult,
    MoveLinearResult,
    PvtPoint,
    SafetyErrorEvent,
    SimResult,
    Status,
    StatusDetail,
    StatusEvent,
    Velocities,
)

__version__ = "0.1.0"


def __getattr__(name: str) -> object:
    # The shared-memory client imports iceoryx2 only when asked for, so the TCP client works
    # without it.
    if name in ("ShmClient", "ControlStats"):
        from . import shm

        return getattr(shm, name)
    raise AttributeError("module 'mcm' has no attribute %r" % name)


__all__ = [
    "Client",
    "ShmClient",
    "ControlStats",
    "DEFAULT_HOST",
    "DEFAULT_PORT",
    "AxisInfo",
    "AxisStates",
    "CartesianState",
    "CommandErrorEvent",
    "Info",
    "InverseKinematicsResult",
    "MoveAllResult",
    "MoveLinearResult",
    "PayloadResult",
    "PvtPoint",
    "SafetyErrorEvent",
    "SimResult",
    "Status",
    "StatusDetail",
    "StatusEvent",
    "CommandError",
    "ErrorCode",
    "ConnectionLost",
    "McmError",
    "McmTimeout",
    "OutcomeUnknown",
    "ProtocolError",
    "ShmUnavailable",
    "Velocities",
]
