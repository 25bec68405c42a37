"""Wheel and rail profiles: the :class:`Profile` type, the standard profiles built from their
definitions and the file readers.

* :mod:`~flexride.contact.profiles.profile` — :class:`Profile` (convention: m, y toward the
  field side, z up; wheel origin at the taping line) and its spline evaluation.
* :mod:`~flexride.contact.profiles.s1002` — S1002 wheel (EN 13715) from its eight sections.
* :mod:`~flexride.contact.profiles.rail60e1` — 60E1 rail head (EN 13674-1) from its arcs.
* :mod:`~flexride.contact.profiles.readers` — SIMPACK ``.prw``/``.prr``, MiniProf
  ``.whl``/``.ban`` and plain text, from files or bytes.
"""

from __future__ import annotations

from flexride.contact.profiles.profile import Profile, ProfileCurve, ProfileKind, SampledProfile
from flexride.contact.profiles.rail60e1 import rail_60e1
from flexride.contact.profiles.readers import read_profile, read_profile_bytes
from flexride.contact.profiles.s1002 import s1002

__all__ = [
    "Profile",
    "ProfileCurve",
    "ProfileKind",
    "SampledProfile",
    "rail_60e1",
    "read_profile",
    "read_profile_bytes",
    "s1002",
]
