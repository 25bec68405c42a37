"""The error of the frequency-domain estimate: the linearised model does not hold."""

from __future__ import annotations

from flexride.errors import FlexrideError

__all__ = ["LinearisationError"]


class LinearisationError(FlexrideError, ValueError):
    """The scenario is outside what a linear, time-invariant model about static equilibrium can
    represent: a transient or periodic excitation instead of a random one, flange contact or a
    lost contact at equilibrium, an unstable linearised system (hunting).

    Parameters
    ----------
    message : str
        The whole message (one line), naming the reason.
    reason : str
        A short key of the reason: ``"excitation"``, ``"flange_contact"``, ``"contact_loss"``,
        ``"unstable"``, ``"equilibrium"``.
    """

    def __init__(self, message: str, reason: str):
        super().__init__(message)
        self.reason = reason
