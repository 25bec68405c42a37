"""Exception types raised by flexride.

Every error the library raises on purpose derives from :class:`FlexrideError`, so callers (the
CLI, the job service) can tell a user mistake from a bug.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

Loc = tuple[str | int, ...]
"""Location of a problem: the field path from the request or scenario root."""


class FlexrideError(Exception):
    """Base class of all flexride errors."""


@dataclass(frozen=True)
class ErrorItem:
    """One problem of an input, located by its field path.

    Attributes
    ----------
    loc : tuple of str or int
        Field path from the root of the input (e.g. ``("excitation", 0, "rows")``); empty for
        the input as a whole.
    msg : str
        What is wrong, with the allowed range where there is one.
    """

    loc: Loc
    msg: str

    @property
    def path(self) -> str:
        """The location as a dotted path (``(root)`` when empty)."""
        return ".".join(str(p) for p in self.loc) or "(root)"


class ScenarioError(FlexrideError, ValueError):
    """A scenario, preset name or input file is invalid.

    The message names the field path and the allowed range where there is one; ``items``
    carries the same as structured :class:`ErrorItem` s when the raiser knows the location.

    Parameters
    ----------
    message : str
        The whole message (one line).
    items : sequence of ErrorItem, optional
        Located problems; the API answers them as 422 items with ``loc``.
    """

    def __init__(self, message: str, items: Sequence[ErrorItem] = ()):
        super().__init__(message)
        self.items: tuple[ErrorItem, ...] = tuple(items)

    @classmethod
    def at(cls, loc: Loc, msg: str, source: str = "scenario") -> ScenarioError:
        """An error with one located problem; the message reads ``source: path: msg``."""
        item = ErrorItem(tuple(loc), msg)
        return cls(f"{source}: {item.path}: {msg}", [item])

    def located(self, prefix: Loc, source: str = "scenario") -> ScenarioError:
        """The same problems located under ``prefix`` (a problem without items becomes one
        item at ``prefix``).
        """
        items = self.items or (ErrorItem((), str(self)),)
        moved = [ErrorItem(tuple(prefix) + it.loc, it.msg) for it in items]
        text = "; ".join(f"{source}: {it.path}: {it.msg}" for it in moved)
        return type(self)(text, moved)


class UnknownPresetError(ScenarioError, KeyError):
    """A preset name that does not exist."""

    def __str__(self) -> str:  # KeyError would quote the message
        """The message as given (KeyError would quote it)."""
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


class StorageError(FlexrideError):
    """The job records or the result, upload or cache files cannot be read or written (a
    read-only or full disk, a database that refuses writes): the service answers 503.
    """


class ResultsFileError(FlexrideError):
    """A results file is missing, unreadable or not a flexride file."""


class FEModelError(FlexrideError, ValueError):
    """A finite-element model is unusable: an input file is unreadable or inconsistent
    (non-symmetric or wrongly sized matrices, missing nodes, negative mass) or the model has
    mechanisms.
    """
