"""Linear models of a parameter sweep, each made reusing what it shares with the previous one.

Every reuse below is exact — the model equals the one
:func:`~flexride.frequency.model.linear_model` builds from scratch, to rounding (the tests
compare the comfort indices within 1e-9 relative):

* **Contact tables** (the conical table or the profiles' table, 40 ms each) are kept by the
  inputs they are made from (:func:`~flexride.solver.assemble.contact_key`); the rest of the
  assembly (a few ms) is made anew (``assemble(..., contact_tables=...)``).
* **Steady state**: chord iterations from the previous value's steady state with its Newton
  matrix (:func:`~flexride.frequency.operating_point.chord_steady_state`), down to steps of
  1e-13: the root a cold start finds, to rounding.
* **Jacobians**: when the kernel's arrays differ only in suspension stiffnesses and dampings
  (``el_k``, ``el_c``) and the contact's state (the coordinates and velocities the wheel
  quantities depend on) has not moved, only the rows and columns of the bodies those
  elements connect change — a suspension element's forces act on its two bodies and depend on
  their coordinates only, and every other force's derivative is the same at the same contact
  state (the vehicle's other forces are affine in the coordinates). Those columns are
  differenced anew and their block of the previous Jacobians replaced; the other columns of
  those bodies are checked to be unchanged on the way (otherwise: all columns). Anything else
  (speed, contact, track, geometry) gets all Jacobians.
* **Track condensation**: reused when the rail rows and columns of the full system are equal
  to the previous ones (:meth:`~flexride.frequency.reduce.Condensation.fits`).

One reuse is not exact: with the statistical linearisation of profile contact the σ iteration
starts from the previous value's σ (and keeps its path samples while the contact's state and
the wheelsets' rows and columns are unchanged), so a value agrees with its rebuild within the
iteration's tolerance (:data:`~flexride.frequency.quasilinear.SIGMA_RTOL`), not to rounding.
"""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.frequency.jacobians import jacobian_columns
from flexride.frequency.lti import SecondOrderSystem
from flexride.frequency.model import (
    DEFAULT_LINEARISATION,
    Linearisation,
    LinearisationMethod,
    LinearModel,
    check_track_model,
    linearise,
    model_from,
    operating_point_or_flag,
    smooth_scenario,
    spectra_or_flag,
)
from flexride.frequency.operating_point import OperatingPoint, WarmStart, warm_start
from flexride.frequency.quasilinear import QuasiLinear, check_linearisation, with_linearisation
from flexride.frequency.reduce import TrackModel
from flexride.scenario.scenario import Scenario
from flexride.solver import assemble as A
from flexride.solver import system as S
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.vehicle.topology import VehicleModel

__all__ = ["ModelRebuilder", "changed_arrays", "same_assembly"]

#: Largest change (m, rad, m/s, rad/s) of a coordinate or velocity the wheel quantities
#: depend on for which the contact's state counts as unchanged: rounding of the steady state.
CONTACT_STATE_TOL = 1e-14
#: A refreshed column outside the replaced block may differ from the previous one by this
#: fraction of the column's largest entry (finite-difference rounding), no more.
COLUMN_CHECK_RTOL = 1e-7
#: Chord iterations above which the warm start's Newton matrix is refactorised (an iteration
#: costs a force evaluation and a triangular solve, 0.1 ms; a refactorisation 5 ms).
CHORD_REFRESH = 12
#: Arrays of the kernel that the kernel writes (scratch), not compared.
_SCRATCH = ("body_line", "el_force")
#: Arrays whose change a partial Jacobian update handles.
_ELEMENT_ARRAYS = {"el_k", "el_c"}
#: How a steady state was found, by :attr:`OperatingPoint.chord_iterations` (else chord).
_START_KINDS = {-1: "cold_start", -2: "newton_from_previous"}


def changed_arrays(a: S.SystemArrays, b: S.SystemArrays) -> set[str]:
    """Names of the kernel's arrays (``par.<name>`` for scalars) that differ between ``a`` and
    ``b`` (scratch arrays aside).
    """
    out = {f"par.{k}" for k, x, y in zip(a.par._fields, a.par, b.par, strict=True) if x != y}
    for name in a._fields:
        if name == "par" or name in _SCRATCH:
            continue
        x, y = getattr(a, name), getattr(b, name)
        if x.shape != y.shape or not np.array_equal(x, y):
            out.add(name)
    return out


def same_assembly(a: A.Assembly, b: A.Assembly) -> bool:
    """Whether two assemblies give the kernel the same arrays and the same coordinates."""
    return (not changed_arrays(a.sys, b.sys) and a.dof_names == b.dof_names
            and np.array_equal(a.static_dofs, b.static_dofs))


def _body_coordinates(sys: S.SystemArrays, bodies: np.ndarray) -> np.ndarray:
    """State indices of every coordinate of ``bodies``."""
    return np.concatenate([np.arange(int(sys.body_off[b]), int(sys.body_off[b] + sys.body_ndof[b]))
                           for b in np.unique(bodies)]).astype(np.int64)


def _contact_unchanged(prev: Linearisation, op: OperatingPoint) -> bool:
    """Whether the coordinates and velocities the wheel quantities depend on (the nonzero
    columns of their derivatives) are where they were when ``prev``'s contact derivatives
    were differenced.
    """
    ref = prev.contact_origin
    if op.X0.shape != ref.X0.shape:
        return False
    cx = np.flatnonzero(np.any(prev.daux_dX != 0.0, axis=0))
    cv = np.flatnonzero(np.any(prev.daux_dV != 0.0, axis=0))
    dx = np.max(np.abs(op.X0[cx] - ref.X0[cx]), initial=0.0)
    dv = np.max(np.abs(op.V0[cv] - ref.V0[cv]), initial=0.0)
    return bool(dx <= CONTACT_STATE_TOL and dv <= CONTACT_STATE_TOL)


def _replace_block(old: np.ndarray, new_cols: np.ndarray, idx: np.ndarray) -> np.ndarray | None:
    """``old`` (a Jacobian) with its block (idx, idx) taken from ``new_cols`` (its columns idx,
    freshly differenced), or None when ``new_cols`` differs from ``old`` outside that block by
    more than rounding.
    """
    rest = np.ones(old.shape[0], dtype=bool)
    rest[idx] = False
    prev_cols = old[:, idx]
    scale = np.maximum(np.abs(new_cols).max(axis=0), 1e-300)
    if np.any(np.abs(new_cols[rest] - prev_cols[rest]) > COLUMN_CHECK_RTOL * scale):
        return None
    out = old.copy()
    out[np.ix_(idx, idx)] = new_cols[idx]
    return out


def _element_update(prev: Linearisation, op: OperatingPoint, idx: np.ndarray
                    ) -> Linearisation | None:
    """``prev`` at ``op`` after a change of suspension elements acting on coordinates ``idx``
    (their rows and columns differenced anew), or None if the check of the other rows fails.
    """
    args = (op.sys, op.X0, op.V0, op.s, op.s_win0)
    dX, _ = jacobian_columns(*args, False, idx, prev.methods_x[idx])
    dV, _ = jacobian_columns(*args, True, idx, prev.methods_v[idx])
    K = _replace_block(prev.full.K, -dX, idx)
    C = _replace_block(prev.full.C, -dV, idx)
    if K is None or C is None:
        return None
    f = prev.full
    full = SecondOrderSystem(K, C, f.B0, f.B1, f.B2)
    return _reusing(prev, op, full)


def _reusing(prev: Linearisation, op: OperatingPoint, full: SecondOrderSystem
             ) -> Linearisation:
    """A linearisation at ``op`` with ``full`` and ``prev``'s contact derivatives."""
    return Linearisation(op, full, prev.mass, prev.daux_dX, prev.daux_dV, prev.daux_du,
                         prev.methods_x, prev.methods_v, prev.contact_origin)


@dataclass
class ModelRebuilder:
    """Linear models of a sequence of scenarios, each reusing what it shares with the
    previous one (module docstring); :meth:`model` returns what
    :func:`~flexride.frequency.model.linear_model` would.

    Parameters
    ----------
    track : {"condensed", "modal", "rigid"}
        Track model.
    strict : bool
        See :func:`~flexride.frequency.model.linear_model`.
    sources : MeasuredSources
        Where measured data and uploaded profiles are read from.
    linearisation : {"statistical", "local"}
        How the contact is linearised (:func:`~flexride.frequency.model.linear_model`); the
        reuse works on the local linearisation, the statistical one is made from it anew.

    Attributes
    ----------
    stats : collections.Counter
        What was reused and what was made anew, by name (``contact_table``,
        ``warm_start``, ``jacobians_partial``, ``jacobians_full``, ``condensation`` …).
    """

    track: TrackModel = "condensed"
    strict: bool = True
    sources: MeasuredSources = LIBRARY
    linearisation: LinearisationMethod = DEFAULT_LINEARISATION
    stats: Counter[str] = field(default_factory=Counter)
    _contacts: dict[str, Any] = field(default_factory=dict, repr=False)
    _previous: LinearModel | None = field(default=None, repr=False)
    _warm: WarmStart | None = field(default=None, repr=False)
    _quasi: QuasiLinear | None = field(default=None, repr=False)
    _samples_hold: bool = field(default=False, repr=False)

    def __post_init__(self) -> None:
        """Refuse an unknown track model or linearisation at once."""
        check_track_model(self.track)
        check_linearisation(self.linearisation)

    def model(self, scenario: Scenario, vehicle: VehicleModel | None = None) -> LinearModel:
        """The linear model of ``scenario``.

        Raises
        ------
        LinearisationError
            As :func:`~flexride.frequency.model.linear_model` (the rebuilder keeps its state
            from the last model that was made).
        """
        t0 = time.perf_counter()
        flags: list[str] = []
        spectra = spectra_or_flag(scenario, self.strict, flags, self.sources)
        asm = self._assemble(smooth_scenario(scenario), vehicle)
        op = operating_point_or_flag(scenario, asm, self.strict, flags, self._warm)
        self.stats[_START_KINDS.get(op.chord_iterations, "warm_start")] += 1
        t1 = time.perf_counter()
        lin = self._linearise(op)
        start = self._quasi.start(self._samples_hold) if self._quasi is not None else None
        # warm-started, the local model serves the quasi-linear one and needs no eigenvectors
        model = model_from(scenario, lin, self.track, spectra, flags, (t0, t1),
                           previous=self._previous, lazy_modes=start is not None)
        prev_red = self._previous.reduced if self._previous is not None else None
        if model.reduced is not None and prev_red is not None and (
                model.reduced.condensation is prev_red.condensation
                and prev_red.condensation is not None):
            self.stats["condensation_reused"] += 1
        self._remember(model, op)
        model = with_linearisation(model, self.linearisation, self.strict, start)
        if model.quasi_linear is not None and model.quasi_linear.applied:
            self._quasi = model.quasi_linear
            self.stats["quasi_linear_warm" if start is not None else "quasi_linear_cold"] += 1
            self.stats["quasi_linear_iterations"] += model.quasi_linear.iterations
        return model

    def _assemble(self, scenario: Scenario, vehicle: VehicleModel | None) -> A.Assembly:
        """The assembly, with the contact tables kept between values."""
        n = len(self._contacts)
        asm = A.assemble(scenario, vehicle, self.sources, contact_tables=self._contacts)
        self.stats["contact_table_made" if len(self._contacts) > n else "contact_table_reused"] += 1
        return asm

    def _linearise(self, op: OperatingPoint) -> Linearisation:
        """Jacobians at ``op``: the previous ones with the changed elements' block replaced
        when that is exact (module docstring), else all of them.
        """
        prev = self._previous.linearisation if self._previous is not None else None
        idx = self._element_coordinates(prev, op) if prev is not None else None
        lin = None
        if prev is not None and idx is not None:
            lin = _element_update(prev, op, idx) if idx.size else _reusing(prev, op, prev.full)
        self.stats["jacobians_partial" if lin is not None else "jacobians_full"] += 1
        # the contact's path samples depend on the contact and the wheelsets' rows and columns
        self._samples_hold = lin is not None and idx is not None and not np.intersect1d(
            idx, _body_coordinates(op.sys, op.sys.ws_body)).size
        return lin if lin is not None else linearise(op)

    @staticmethod
    def _element_coordinates(prev: Linearisation, op: OperatingPoint) -> np.ndarray | None:
        """Coordinates of the bodies whose suspension elements changed since ``prev``, when
        nothing else did and the contact's state stayed; else None.
        """
        a, b = prev.op.sys, op.sys
        changed = changed_arrays(a, b)
        if not changed <= _ELEMENT_ARRAYS or (prev.op.s, prev.op.s_win0) != (op.s, op.s_win0):
            return None
        if a.el_k.shape != b.el_k.shape or not _contact_unchanged(prev, op):
            return None
        rows = np.flatnonzero(np.any(a.el_k != b.el_k, axis=1) | np.any(a.el_c != b.el_c, axis=1))
        if rows.size == 0:
            return np.zeros(0, dtype=np.int64)
        return _body_coordinates(b, np.concatenate([b.el_a[rows], b.el_b[rows]]))

    def _remember(self, model: LinearModel, op: OperatingPoint) -> None:
        """Keep ``model`` for the next value and update the warm start."""
        self._previous = model
        lin = model.linearisation
        assert lin is not None
        if self._warm is None or op.chord_iterations < 0 or op.chord_iterations > CHORD_REFRESH:
            self._warm = warm_start(op, -lin.full.K, -lin.full.C)
            self.stats["newton_matrix"] += 1
        else:
            w = self._warm
            self._warm = WarmStart(op.X0.copy(), op.V0.copy(), op.s, op.s_win0, w.lu)
