"""Exception types raised by flexride.

Every error the library raises on purpose derives from :class:`FlexrideError`, so callers (the
CLI, the job service) can tell a user mistake from a bug.
"""

from __future__ import annotations


class FlexrideError(Exception):
    """Base class of all flexride errors."""


class ScenarioError(FlexrideError, ValueError):
    """A scenario, preset name or input file is invalid.

    The message names the field path and the allowed range where there is one.
    """


class UnknownPresetError(ScenarioError, KeyError):
    """A preset name that does not exist."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class StabilityError(FlexrideError):
    """The time step is beyond the explicit integrator's stability limit.

    Attributes
    ----------
    dt : float
        Requested time step in s.
    dt_max : float
        Largest stable time step estimated for the linearised system in s.
    dt_suggested : float
        A step that works (with margin) in s.
    """

    def __init__(self, message: str, dt: float, dt_max: float, dt_suggested: float):
        super().__init__(message)
        self.dt = dt
        self.dt_max = dt_max
        self.dt_suggested = dt_suggested


class SimulationError(FlexrideError):
    """The integration diverged (NaN, inf or runaway growth)."""


class SimulationCancelled(FlexrideError):
    """The run was cancelled through the cooperative cancel callback."""


class AnalysisError(FlexrideError, ValueError):
    """Input to an analysis function is unusable (empty, NaN, too short, sample rate too low)."""


class ResultsFileError(FlexrideError):
    """A results file is missing, unreadable or not a flexride file."""


class FEModelError(FlexrideError, ValueError):
    """A finite-element model is unusable: an input file is unreadable or inconsistent
    (non-symmetric or wrongly sized matrices, missing nodes, negative mass) or the model has
    mechanisms."""
