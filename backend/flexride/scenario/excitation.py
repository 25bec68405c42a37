"""Track excitation (track irregularity) schemas.

A scenario lists any number of excitations; they are summed into one rail irregularity profile
by :func:`flexride.track.excitation.build_profile`. Each kind is selected by its ``kind``
field (a pydantic discriminated union, :data:`Excitation`):

``"random"``       :class:`RandomIrregularity` — stationary Gaussian irregularity from the German
                   track spectra (DESIGN §6), band-limited in wavelength.
``"corrugation"``  :class:`Corrugation` — continuous sinusoidal short-wave excitation.
``"settlement"``   :class:`Settlement` — a single cosine dip (long-wave excitation).
``"measured"``     :class:`MeasuredIrregularity` — measured irregularities: a CSV file, an
                   uploaded CSV (service) or rows given inline.

Conventions (DESIGN §4): SI units, x along the track, y to the left, z up. Vertical rail
irregularities are positive upwards, lateral ones positive to the left (so a positive gauge
deviation, the left rail moving to +y and the right rail to −y, widens the gauge). Left rail at
y = +b, right rail at y = −b.
"""

from __future__ import annotations

import itertools
import math
from typing import Annotated, Literal, Self

from pydantic import Field, field_validator, model_validator

from flexride.scenario.base import Schema, quantity

__all__ = [
    "IRREGULARITY_COMPONENTS",
    "Component",
    "Corrugation",
    "Excitation",
    "MeasuredIrregularity",
    "Rails",
    "RandomIrregularity",
    "Settlement",
    "SpectrumName",
    "SpectrumTable",
]

Component = Literal["vertical", "alignment", "cross_level", "gauge"]
"""An irregularity component: vertical profile, alignment, cross level or gauge."""

IRREGULARITY_COMPONENTS: tuple[Component, ...] = ("vertical", "alignment", "cross_level", "gauge")
"""All components, in the fixed order that also fixes each component's random stream."""

SpectrumName = Literal["german-high", "german-low", "table"]
"""Track spectrum: German high- or low-disturbance level, or the user's table."""

MAX_TABLE_POINTS = 1000
"""Most points of a tabulated spectrum."""


class SpectrumTable(Schema):
    """A user's one-sided track spectra S(Ω), e.g. a national standard's or a recording's.

    Values at the spatial angular frequencies ``omega_rad_per_m`` (strictly increasing), one
    list per component given (the same length); between points the spectrum is interpolated
    linearly in log S against log Ω (power laws stay exact), outside them it is zero. Units as
    the German spectra's: m²/(rad/m), for cross level the spectrum of the cross-level angle in
    rad²/(rad/m) (a rail height difference Δz = 2b·angle has the spectrum 4b²·S).
    """

    omega_rad_per_m: list[float] = quantity(
        ..., min_length=2, max_length=MAX_TABLE_POINTS, unit="rad/m",
        description="Spatial angular frequencies Ω = 2π/λ of the table, increasing")
    vertical: list[float] | None = quantity(
        None, max_length=MAX_TABLE_POINTS, unit="m²/(rad/m)",
        description="Vertical profile spectrum at each Ω")
    alignment: list[float] | None = quantity(
        None, max_length=MAX_TABLE_POINTS, unit="m²/(rad/m)",
        description="Alignment spectrum at each Ω")
    cross_level: list[float] | None = quantity(
        None, max_length=MAX_TABLE_POINTS, unit="rad²/(rad/m)",
        description="Cross-level angle spectrum at each Ω")
    gauge: list[float] | None = quantity(
        None, max_length=MAX_TABLE_POINTS, unit="m²/(rad/m)",
        description="Gauge spectrum at each Ω")

    @model_validator(mode="after")
    def _consistent(self) -> Self:
        om = self.omega_rad_per_m
        if not all(math.isfinite(w) and w > 0.0 for w in om) or any(
                b <= a for a, b in itertools.pairwise(om)):
            raise ValueError("omega_rad_per_m must be positive, finite and strictly increasing")
        for name in IRREGULARITY_COMPONENTS:
            values = getattr(self, name)
            if values is None:
                continue
            if len(values) != len(om):
                raise ValueError(f"{name} has {len(values)} values for {len(om)} frequencies")
            if not all(math.isfinite(v) and v >= 0.0 for v in values):
                raise ValueError(f"{name}: spectrum values must be finite and >= 0")
        if not self.components():
            raise ValueError("give the spectrum of at least one component")
        return self

    def components(self) -> tuple[str, ...]:
        """Components the table gives."""
        return tuple(c for c in IRREGULARITY_COMPONENTS if getattr(self, c) is not None)

Rails = Literal["both", "left", "right"]
"""Which rail a local (vertical) defect is on."""


class RandomIrregularity(Schema):
    """Random track irregularity from the German track spectra.

    A stationary zero-mean Gaussian realisation of the one-sided spectra of DESIGN §6
    (m²/(rad/m) against spatial angular frequency Ω in rad/m), restricted to the wavelength band
    ``wavelength_min_m`` … ``wavelength_max_m`` (hard band edges, no taper). The four components
    are statistically independent; each is drawn from its own random stream derived from
    ``seed``, so switching one component off does not change the others.

    Rail mapping (see :mod:`flexride.track.spectra`): with b = 0.75 m,
    z_left = z_v + b·c, z_right = z_v − b·c (c the cross-level angle in rad, so the rail height
    difference is 2b·c), y_left = y_a + g/2, y_right = y_a − g/2 (g the gauge deviation,
    widening positive).
    """

    kind: Literal["random"] = "random"
    spectrum: SpectrumName = Field(
        "german-high", description="Track spectrum: German high or low disturbance, or "
        "'table' (the user's spectra in 'table') (-)"
    )
    table: SpectrumTable | None = Field(
        None, description="The spectra when spectrum is 'table' (S(Ω) per component)")
    components: list[Component] = Field(
        default_factory=lambda: list(IRREGULARITY_COMPONENTS),
        min_length=1,
        description="Irregularity components to generate (-); each at most once",
    )
    wavelength_min_m: float = quantity(
        1.0, ge=0.1, le=50.0, description="Shortest wavelength of the band", unit="m"
    )
    wavelength_max_m: float = quantity(
        120.0, gt=0.1, le=1000.0, description="Longest wavelength of the band", unit="m"
    )
    seed: int = quantity(1, ge=0, description="Seed of the random generator", unit="-")
    scale: float = quantity(
        1.0, ge=0.0, le=10.0, description="Amplitude factor applied to the realisation", unit="-"
    )

    @field_validator("components")
    @classmethod
    def _unique_components(cls, value: list[Component]) -> list[Component]:
        duplicates = sorted({c for c in value if value.count(c) > 1})
        if duplicates:
            raise ValueError(f"components must be unique; repeated: {', '.join(duplicates)}")
        return value

    @model_validator(mode="after")
    def _band_order(self) -> Self:
        if not self.wavelength_max_m > self.wavelength_min_m:
            raise ValueError(
                f"wavelength_max_m ({self.wavelength_max_m} m) must exceed "
                f"wavelength_min_m ({self.wavelength_min_m} m)"
            )
        return self

    @model_validator(mode="after")
    def _table_given(self) -> Self:
        if (self.spectrum == "table") != (self.table is not None):
            raise ValueError("give 'table' exactly when spectrum is 'table'")
        if self.table is not None:
            missing = [c for c in self.components if c not in self.table.components()]
            if missing:
                raise ValueError(f"the table has no spectrum of {', '.join(missing)} "
                                 "(components asks for it)")
        return self


class Corrugation(Schema):
    """Rail corrugation: continuous sinusoidal short-wave vertical excitation.

    The rail head follows z = −(depth/2)·(1 − cos(2π(s − start)/λ)) over a whole number of
    wavelengths starting at ``start_m`` (troughs below the nominal rail level, smooth entry and
    exit). Lateral irregularities are not affected.

    Note on the paper's values: the paper prints "wavelength 0.5 mm, depth 1 mm", which is
    physically impossible (a 0.5 mm wave is far shorter than the ~10 mm wheel–rail contact
    patch and could not be followed by the wheel). It is read as 0.5 m wavelength and 1 mm
    depth, the defaults here.
    """

    kind: Literal["corrugation"] = "corrugation"
    wavelength_m: float = quantity(
        0.5, ge=0.01, le=5.0, description="Corrugation wavelength", unit="m"
    )
    depth_m: float = quantity(
        0.001, ge=0.0, le=0.01, description="Corrugation depth, peak to peak", unit="m"
    )
    start_m: float = quantity(
        0.0, ge=0.0, description="Distance along the line where the corrugation starts", unit="m"
    )
    length_m: float | None = quantity(
        None,
        gt=0.0,
        description="Length of the corrugated stretch; null = to the end of the route",
        unit="m",
    )
    rails: Rails = Field("both", description="Corrugated rail(s) (-)")


class Settlement(Schema):
    """Track settlement: a single cosine dip (long-wave vertical excitation).

    z = −(depth/2)·(1 − cos(2π(s − s0)/λ)) for s0 ≤ s ≤ s0 + λ, zero elsewhere, with
    s0 = ``position_m``: the deepest point (z = −depth) is at s0 + λ/2. Lateral irregularities
    are not affected. The paper's long-wave case is λ = 20 m, depth = 10 cm (the defaults).
    """

    kind: Literal["settlement"] = "settlement"
    wavelength_m: float = quantity(
        20.0, ge=1.0, le=500.0, description="Length of the dip", unit="m"
    )
    depth_m: float = quantity(0.1, ge=0.0, le=0.5, description="Depth of the dip", unit="m")
    position_m: float = quantity(
        50.0, ge=0.0, description="Distance along the line where the dip starts", unit="m"
    )
    rails: Rails = Field("both", description="Settled rail(s) (-)")


class MeasuredIrregularity(Schema):
    """Measured irregularities (e.g. a track recording): a CSV file, an uploaded CSV or rows.

    Give the data in exactly one way:

    * ``path``: a CSV file on the machine that runs the simulation (CLI and library; refused
      by the service's API, where a request never names a server file);
    * ``upload``: the id (SHA-256 of the content) of a CSV uploaded to the service with
      ``POST /api/v1/irregularities``;
    * ``columns`` and ``rows``: the same table inline, column names and one row of values per
      measurement point.

    CSV format: comma separated, UTF-8, one header row naming the columns, then one row per
    measurement point. Blank lines and lines starting with ``#`` are ignored. Columns:

    * the distance column (``distance_column``, m along the line), strictly increasing, with a
      median spacing of at least 1 mm;
    * any of the component columns, in m:
      ``vertical`` (mean of both rails, up positive), ``alignment`` (mean lateral position,
      left positive), ``cross_level`` (rail height difference z_left − z_right, positive when
      the left rail is higher), ``gauge`` (gauge deviation y_left − y_right, widening positive);
    * and/or per-rail columns ``z_left``, ``z_right`` (vertical, up positive) and ``y_left``,
      ``y_right`` (lateral, left positive), in m.

    All given columns are added: z_left = vertical + cross_level/2 + z_left column,
    z_right = vertical − cross_level/2 + z_right column, y_left = alignment + gauge/2 + y_left
    column, y_right = alignment − gauge/2 + y_right column. Other columns are ignored. The data
    are resampled linearly onto the profile grid and are zero outside the measured stretch.
    """

    kind: Literal["measured"] = "measured"
    path: str | None = Field(
        None,
        min_length=1,
        max_length=4096,
        description="CSV file on the machine that runs the simulation (-); CLI and library "
        "only, refused by the API",
    )
    upload: str | None = Field(
        None,
        pattern=r"^[0-9a-f]{64}$",
        description="Id (SHA-256 of the content) of a CSV uploaded with "
        "POST /api/v1/irregularities (-)",
    )
    columns: list[Annotated[str, Field(min_length=1, max_length=64)]] | None = Field(
        None,
        min_length=2,
        max_length=64,
        description="Column names of the inline rows (-), as a CSV header",
    )
    rows: list[list[float]] | None = Field(
        None,
        min_length=2,
        description="Inline measurement rows (m): one value per column of 'columns'",
    )
    distance_column: str = Field(
        "distance_m",
        min_length=1,
        max_length=64,
        description="Name of the distance column (m) in the data",
    )
    scale: float = quantity(
        1.0, ge=0.0, le=10.0, description="Amplitude factor applied to the measured data", unit="-"
    )

    @model_validator(mode="after")
    def _one_source(self) -> Self:
        given = [n for n in ("path", "upload", "rows") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError(
                "give the data in exactly one way: 'path' (a file, CLI and "
                "library), 'upload' (an uploaded CSV's id) or 'columns' + 'rows'"
                + (f"; got {', '.join(given)}" if given else "")
            )
        if (self.rows is None) != (self.columns is None):
            raise ValueError("'rows' need 'columns' (the column names) and vice versa")
        return self


Excitation = Annotated[
    RandomIrregularity | Corrugation | Settlement | MeasuredIrregularity,
    Field(discriminator="kind"),
]
"""Any track excitation, selected by its ``kind`` field."""
