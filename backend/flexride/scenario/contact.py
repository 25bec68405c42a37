"""Wheel–rail contact settings."""

from __future__ import annotations

from typing import Literal, Self

from pydantic import Field, model_validator

from flexride.contact.placement import Placement
from flexride.scenario.base import Schema, quantity

_PLACEMENT = Placement()
"""Default wheel–rail placement (the one source of gauge and gauge height defaults)."""

BUILTIN_WHEELS = ("s1002",)
"""Built-in wheel profiles (:mod:`flexride.contact.profiles`)."""
BUILTIN_RAILS = ("60e1",)
"""Built-in rail profiles."""


class ProfileSource(Schema):
    """One wheel or rail profile, given in exactly one way.

    * ``builtin``: a profile flexride builds from its definition (wheel ``s1002`` of EN 13715,
      rail ``60e1`` of EN 13674-1);
    * ``path``: a profile file on the machine that runs the simulation (SIMPACK ``.prw``/``.prr``,
      MiniProf ``.whl``/``.ban`` or two-column text in mm; CLI and library only, refused by the
      service's API, where a request never names a server file);
    * ``upload``: the id (SHA-256 of the content) of a profile file stored by the service.
    """

    builtin: str | None = Field(None, min_length=1, max_length=32,
                                description="Name of a built-in profile (-)")
    path: str | None = Field(None, min_length=1, max_length=4096,
                             description="Profile file on the machine that runs the simulation "
                             "(-); CLI and library only, refused by the API")
    upload: str | None = Field(None, pattern=r"^[0-9a-f]{64}$",
                               description="Id (SHA-256 of the content) of an uploaded profile "
                               "file (-)")

    @model_validator(mode="after")
    def _one_source(self) -> Self:
        given = [n for n in ("builtin", "path", "upload") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("give the profile in exactly one way: 'builtin', 'path' (a file, "
                             "CLI and library) or 'upload' (an uploaded file's id)"
                             + (f"; got {', '.join(given)}" if given else ""))
        return self


class Contact(Schema):
    """Wheel–rail contact: tread geometry, Hertz normal contact, Kalker creep with saturation.

    ``geometry`` selects the contact geometry:

    * ``conical``: a conical tread of equivalent conicity ``conicity`` on a rail head of radius
      ``rail_head_radius``, one contact point per wheel, flange contact as a stiff lateral
      spring beyond the flangeway clearance (``flange_clearance``, ``flange_stiffness``), Zhai's
      normal constant (``hertz_tread``);
    * ``profiles``: real wheel and rail profiles (``wheel``, ``rail``) placed in the track
      (``inclination``, ``gauge``, ``gauge_height``, ``flange_back_distance``; the nominal rolling
      radius is the vehicle's wheel radius), two contact slots per wheel (tread and flange
      branch), each with its own contact angle, normal force and creep forces; the flange is
      part of the geometry (no spring). Normal constant from the curvatures (``normal``).
    """

    geometry: Literal["conical", "profiles"] = Field(
        "conical", description="Contact geometry model: conical tread or real profiles (-)")
    profile: Literal["conical"] = Field(
        "conical", description="Tread geometry of the conical model (kept for old scenarios; "
        "use 'geometry') (-)")
    conicity: float = quantity(
        0.05, ge=0.0, le=0.5, description="Equivalent conicity tan(γ) of the conical tread",
        unit="-"
    )
    hertz_tread: Literal["worn", "conical"] = Field(
        "worn",
        description="Conical geometry: which Zhai Hertz constant G to use: worn/LM tread "
        "3.86·R^-0.115e-8 or conical 4.57·R^-0.149e-8 (m/N^(2/3))",
    )
    rail_head_radius: float = quantity(
        0.3, gt=0.01, le=10.0, description="Transverse radius of the rail head (conical geometry)",
        unit="m"
    )
    friction: float = quantity(
        0.3, gt=0.0, le=1.0, description="Wheel–rail friction coefficient", unit="-"
    )
    shear_modulus: float | None = quantity(
        None, gt=1e9, le=2e11, description="Shear modulus of wheel and rail steel; default "
        "8e10 Pa for the conical geometry and E/(2(1 + ν)) (E of the rail) for profiles",
        unit="Pa"
    )
    poisson: float = quantity(
        0.28, ge=0.0, le=0.5, description="Poisson's ratio of steel", unit="-"
    )
    flange_clearance: float = quantity(
        0.008,
        gt=0.0,
        le=0.05,
        description="Conical geometry: lateral wheelset displacement at which the flange touches",
        unit="m",
    )
    flange_stiffness: float = quantity(
        1.5e8, gt=1e5, le=1e10,
        description="Conical geometry: lateral contact stiffness of the flange", unit="N/m"
    )
    wheel: ProfileSource = Field(
        default_factory=lambda: ProfileSource(builtin="s1002"),
        description="Profiles geometry: wheel profile (-)")
    rail: ProfileSource = Field(
        default_factory=lambda: ProfileSource(builtin="60e1"),
        description="Profiles geometry: rail profile (-)")
    inclination: Literal["1:40", "1:20", "none"] = Field(
        "1:40", description="Profiles geometry: rail inclination toward the track centre "
        "('none' for a rail file that is already canted) (-)")
    gauge: float = quantity(
        _PLACEMENT.gauge, ge=1.0, le=1.7, description="Profiles geometry: track gauge", unit="m")
    gauge_height: float = quantity(
        _PLACEMENT.gauge_height, ge=0.005, le=0.02,
        description="Profiles geometry: height below the top of rail where the gauge is "
        "measured (14 mm Europe, 16 mm China)", unit="m")
    flange_back_distance: float | None = quantity(
        None, ge=0.9, le=1.6, description="Profiles geometry: distance between the flange backs "
        "of a wheelset; default 2·(rolling-circle half distance − 70 mm) of the vehicle, so that "
        "the taping lines are the vehicle's rolling circles (1.353 m for the paper's b0 = "
        "0.7465 m)", unit="m")
    normal: Literal["hertz", "zhai-worn", "zhai-conical"] = Field(
        "hertz", description="Profiles geometry: normal contact constant from Hertz theory with "
        "the profiles' curvatures, or Zhai's empirical constants (-)")

    @model_validator(mode="after")
    def _builtins(self) -> Self:
        for name, src, known in (("wheel", self.wheel, BUILTIN_WHEELS),
                                 ("rail", self.rail, BUILTIN_RAILS)):
            if src.builtin is not None and src.builtin.lower() not in known:
                raise ValueError(f"{name}.builtin: unknown {name} profile {src.builtin!r}; "
                                 f"built in: {', '.join(known)}")
        return self

    def shear_modulus_for(self, youngs_modulus: float) -> float:
        """Shear modulus in Pa: the given one, else 8e10 Pa (conical geometry) or
        E/(2(1 + ν)) with the rail's Young's modulus E in Pa (profiles).
        """
        if self.shear_modulus is not None:
            return float(self.shear_modulus)
        if self.geometry == "conical":
            return 8.0e10
        return float(youngs_modulus) / (2.0 * (1.0 + float(self.poisson)))
