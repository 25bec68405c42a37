"""The contact table of a scenario's ``contact`` settings with ``geometry: profiles``.

Profiles come from the built-in definitions, from files (library and CLI) or from uploads
(the service's content-addressed files, ``<sha256>.<ext>`` in the upload directory); where they
may be read from is the caller's :class:`~flexride.track.measured.MeasuredSources`, the same
rule as for measured irregularities: the service never reads a path named by a request.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from pathlib import Path

from flexride.contact.placement import Placement
from flexride.contact.profile_table import ProfileContactTable, profile_contact_table
from flexride.contact.profiles import Profile, rail_60e1, read_profile, read_profile_bytes, s1002
from flexride.errors import ScenarioError
from flexride.scenario.contact import Contact, ProfileSource
from flexride.track.measured import LIBRARY, MeasuredSources

__all__ = ["PROFILE_EXTENSIONS", "TAPING_LINE_OFFSET", "load_profile", "placement_for",
           "scenario_contact_table"]

#: Extensions an uploaded profile may be stored with (the format follows the extension).
PROFILE_EXTENSIONS = (".prw", ".prr", ".whl", ".ban", ".txt", ".csv")
#: Flange back to taping line, m (EN 13715).
TAPING_LINE_OFFSET = 0.070


@functools.cache
def _builtin(kind: str, name: str) -> Profile | None:
    """A built-in profile, built once per process (S1002 takes 12 ms: every submission to the
    service loads the scenario's profiles to check them), or None for an unknown name.
    """
    makers: dict[tuple[str, str], Callable[[], Profile]] = {("wheel", "s1002"): s1002,
                                                            ("rail", "60e1"): rail_60e1}
    make = makers.get((kind, name))
    if make is None:
        return None
    profile = make()
    for points in (profile.y, profile.z):  # shared: nobody may change it
        points.flags.writeable = False
    return profile


def load_profile(src: ProfileSource, kind: str, sources: MeasuredSources = LIBRARY) -> Profile:
    """The profile ``src`` of ``kind`` (``"wheel"`` or ``"rail"``).

    Raises
    ------
    ScenarioError
        Located at ``builtin``, ``path`` or ``upload``: unknown name, a path where paths are
        not allowed, a missing upload or an unreadable file.
    """
    if src.builtin is not None:
        profile = _builtin(kind, src.builtin.lower())
        if profile is None:
            raise ScenarioError.at(("builtin",), f"unknown built-in {kind} profile "
                                                 f"{src.builtin!r}")
        return profile
    if src.path is not None:
        if not sources.allow_paths:
            raise ScenarioError.at(("path",), "a profile file path is not accepted here; upload "
                                   "the file and give its id as 'upload'")
        try:
            return read_profile(src.path, kind)  # type: ignore[arg-type]
        except ScenarioError as err:
            raise err.located(("path",)) from None
    upload = str(src.upload)
    if sources.upload_dir is not None:
        for ext in PROFILE_EXTENSIONS:
            f = Path(sources.upload_dir) / f"{upload}{ext}"
            if f.is_file():
                try:
                    return read_profile_bytes(f.read_bytes(), f"upload{ext}", kind)  # type: ignore[arg-type]
                except ScenarioError as err:
                    raise err.located(("upload",)) from None
    raise ScenarioError.at(("upload",), f"no uploaded profile with id {upload[:12]}…")


def placement_for(contact: Contact, r0: float, b0: float) -> Placement:
    """The placement of ``contact``'s profiles for a vehicle with wheel radius ``r0`` and
    rolling-circle half distance ``b0`` (m): the flange-back distance defaults to
    2·(b0 − 70 mm), so that the taping lines are the vehicle's rolling circles.
    """
    fb = contact.flange_back_distance
    if fb is None:
        fb = 2.0 * (b0 - TAPING_LINE_OFFSET)
    incl = {"1:40": "1:40", "1:20": "1:20", "none": "none"}[contact.inclination]
    return Placement(inclination=incl, gauge=contact.gauge,  # type: ignore[arg-type]
                     gauge_height=contact.gauge_height, flange_back=fb, r0=r0,
                     taping_line_offset=TAPING_LINE_OFFSET)


def scenario_contact_table(contact: Contact, r0: float, b0: float, youngs_modulus: float,
                           sources: MeasuredSources = LIBRARY) -> ProfileContactTable:
    """The two-slot contact table of ``contact`` (``geometry: profiles``), cached on disk.

    Errors are located under ``wheel``/``rail`` (profiles) or at the contact itself.
    """
    profiles = []
    for name, src in (("wheel", contact.wheel), ("rail", contact.rail)):
        try:
            profiles.append(load_profile(src, name, sources))
        except ScenarioError as err:
            raise err.located((name,)) from None
    placement = placement_for(contact, r0, b0)
    return profile_contact_table(
        profiles[0], profiles[1], placement, E=youngs_modulus, nu=contact.poisson,
        shear_modulus=contact.shear_modulus_for(youngs_modulus), normal=contact.normal)
