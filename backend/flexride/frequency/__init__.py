"""Frequency-domain ride comfort: the linearised vehicle–track model's response to the track
spectra, cross-checked against the time-domain solver (``docs/analysis.md``, "Frequency-domain
estimate").

Typical use (the costly part is :func:`linear_model`, once per scenario)::

    from flexride.frequency import comfort, linear_model, response
    from flexride.scenario.presets import load_preset

    model = linear_model(load_preset("paper-random-straight-80"))
    table = comfort(response(model))          # every car-body point
    table.to_dict()                           # JSON-able

:func:`estimate` does the three steps; :func:`sweep` repeats them over values of one
scenario field, rebuilding each model reusing what the value does not change
(:class:`ModelRebuilder`, exact to rounding); :func:`linear_time_history` applies the model to
a given profile.
"""

from __future__ import annotations

from flexride.frequency.comfort import ComfortTable, DirectionComfort, PointComfort, comfort
from flexride.frequency.errors import LinearisationError
from flexride.frequency.estimate import Estimate, estimate
from flexride.frequency.grid import frequency_grid
from flexride.frequency.lti import Modes, OutputMap, SecondOrderSystem, output_frf
from flexride.frequency.model import LinearModel, linear_model
from flexride.frequency.rebuild import ModelRebuilder
from flexride.frequency.response import ResponseSpectra, response
from flexride.frequency.sweep import SweepResult, sweep, sweep_scenarios
from flexride.frequency.timehistory import linear_time_history
from flexride.frequency.track_input import RandomInput, TrackSpectra, track_spectra

__all__ = [
    "ComfortTable",
    "DirectionComfort",
    "Estimate",
    "LinearModel",
    "LinearisationError",
    "ModelRebuilder",
    "Modes",
    "OutputMap",
    "PointComfort",
    "RandomInput",
    "ResponseSpectra",
    "SecondOrderSystem",
    "SweepResult",
    "TrackSpectra",
    "comfort",
    "estimate",
    "frequency_grid",
    "linear_model",
    "linear_time_history",
    "output_frf",
    "response",
    "sweep",
    "sweep_scenarios",
    "track_spectra",
]
