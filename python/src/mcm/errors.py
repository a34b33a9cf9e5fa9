"""The exceptions of the MCM client. Every one is an :class:`McmError`."""

from typing import Optional


class McmError(Exception):
    """Base class of every error this package raises."""


class CommandError(McmError):
    """The MCM refused a command, or the command failed while running.

    Attributes:
        command: the command's protocol name (``"move_axis"``).
        message: the MCM's own words (the JSON ``error_message``).
        code: the error code, an :class:`mcm.codes.ErrorCode` (a ``str``: ``"busy"``,
            ``"not_owner"``, ``"wrong_mode"``, ...): over TCP the result's ``error_code`` (None
            for a code this version does not know), over shared memory the core's code. Decide
            on it, never on the words.
        outcome: ``"refused"`` (nothing changed), ``"failed"`` (accepted, then failed),
            ``"unknown"`` (no reply came: the command may or may not have run), or
            ``"invalid"`` (the gateway refused the arguments).
    """

    def __init__(
        self,
        command: str,
        message: str,
        code: Optional[str] = None,
        outcome: str = "refused",
    ) -> None:
        super().__init__(message)
        self.command = command
        self.message = message
        self.code = code
        self.outcome = outcome

    def __repr__(self) -> str:
        return "CommandError(command=%r, code=%r, outcome=%r, message=%r)" % (
            self.command,
            self.code,
            self.outcome,
            self.message,
        )


class OutcomeUnknown(CommandError):
    """No answer came in time: the command may or may not have been executed; read the state."""


class McmTimeout(McmError, TimeoutError):
    """A wait ended before its answer came (TCP: the connection is closed, see
    :meth:`mcm.Client.reconnect`)."""


class ConnectionLost(McmError, ConnectionError):
    """The connection to the MCM is closed or broken."""


class ProtocolError(McmError):
    """The MCM sent something this client cannot read (another MCM version?)."""


class ShmUnavailable(McmError):
    """The shared-memory client cannot be used: the ``iceoryx2`` package (``pip install
    mcm[shm]``) is missing, or the MCM's services of the instance do not exist or do not
    match this client's layouts."""
