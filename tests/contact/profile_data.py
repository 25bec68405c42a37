"""Test data of the contact-geometry tests: the profile files in ``shared/profiles`` beside the
repository (CI keeps a copy of ``shared/`` next to the clone) and this folder's ``data/``.

Import as ``from contact.profile_data import …`` (``tests`` is on the path)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from flexride.contact.profiles import Profile

REPO = Path(__file__).resolve().parents[2]
SHARED = (REPO / ".." / "shared").resolve()
DATA = Path(__file__).resolve().parent / "data"


def shared_file(*parts: str) -> Path:
    """A file under ``shared/`` beside the clone; a missing file fails the test (never skips):
    these are the oracles of the contact-geometry tests."""
    path = SHARED.joinpath(*parts)
    if not path.is_file():
        pytest.fail(
            f"test data {path} is missing: the contact tests read the profile files from "
            "shared/profiles/ next to the repository clone (see shared/profiles/README.md)",
            pytrace=False,
        )
    return path


def mbench_file(name: str) -> Path:
    """A file of the Manchester contact benchmark (``MBench_S1002_v3.prw``, ``…UIC60_v3.prr``,
    ``…UIC60_v3.ban``)."""
    return shared_file("profiles", "contact_mbench", name)


def en15302_file(name: str) -> Path:
    """A reference profile of EN 15302 Annex D (``RUIC519A.dat`` …, ``SUIC519A.dat``)."""
    return shared_file("profiles", "en15302_reference_profiles", name)


LAM = 0.02


def cone_wheel(lam: float = LAM) -> Profile:
    """A cone of conicity λ (radius growing toward the flange) with a steep flange beyond
    s = −40 mm."""
    s = np.linspace(-60.0, 60.0, 2401)
    z = np.where(s >= -40.0, lam * s, lam * -40.0 - 0.7 * (-40.0 - s))
    return Profile("wheel", s * 1e-3, z * 1e-3, "cone")


def crown_rail(radius_mm: float = 300.0) -> Profile:
    """A round head of radius R over |u| ≤ 25 mm with 1:20 sides down to 30 mm."""
    u = np.linspace(-25.0, 25.0, 2001)
    v = -(radius_mm - np.sqrt(radius_mm**2 - u**2))
    edge = float(v[0])
    side = np.linspace(edge - 0.5, -30.0, 60)
    du = (edge - side) / 20.0
    uu = np.concatenate([-25.0 - du[::-1], u, 25.0 + du])
    vv = np.concatenate([side[::-1], v, side])
    return Profile("rail", uu * 1e-3, vv * 1e-3, "crown R300")
