"""Wheel–rail contact: Hertz normal contact, Kalker creep coefficients, saturated creep forces
and tabulated contact geometry.

* :mod:`flexride.contact.hertz` — Zhai's Hertz constant and spring, the Hertz contact ellipse.
* :mod:`flexride.contact.kalker` — Kalker's linear creep coefficients C_ij and f_ij.
* :mod:`flexride.contact.creep` — compiled Kalker + Shen–Hedrick–Elkins creep forces.
* :mod:`flexride.contact.geometry` — :class:`ContactTable`, the conical builder and the
  compiled interpolation / flange helpers.
* :mod:`flexride.contact.profiles` — wheel and rail profiles (S1002, 60E1, file readers).
* :mod:`flexride.contact.placement` — placement of the profiles in the track.
* :mod:`flexride.contact.search` — rigid contact-point search over the lateral displacement.
* :mod:`flexride.contact.profile_table` — two-point contact tables of a profile pair (cached).
* :mod:`flexride.contact.conicity` — equivalent conicity (EN 15302 integration, harmonic).

Importing this package compiles nothing: the numba functions compile on first call (and are
cached on disk). The profile modules (profiles, placement, search, profile_table, conicity) are
not imported here, so the solver's start-up does not load them; import them by module.
"""

from __future__ import annotations

from flexride.contact.creep import creep_forces, she_saturation
from flexride.contact.geometry import (
    TABLE_FIELDS,
    TABLE_PARAMS,
    ContactTable,
    conical_table,
    flange_force,
    interp_uniform,
)
from flexride.contact.hertz import hertz_constant, hertz_contact, hertz_ellipse, hertz_force
from flexride.contact.kalker import creep_coefficients, kalker_coefficients, kalker_from_axes

__all__ = [
    "TABLE_FIELDS",
    "TABLE_PARAMS",
    "ContactTable",
    "conical_table",
    "creep_coefficients",
    "creep_forces",
    "flange_force",
    "hertz_constant",
    "hertz_contact",
    "hertz_ellipse",
    "hertz_force",
    "interp_uniform",
    "kalker_coefficients",
    "kalker_from_axes",
    "she_saturation",
]
