"""Bodies of the results routes: channels, points, series, spectra, Sperling, correlation."""

from __future__ import annotations

from typing import Literal

from pydantic import (
    BaseModel,
    Field,
)

# -- results ---------------------------------------------------------------------------------


class ChannelInfo(BaseModel):
    """A recorded channel ``<body>.<point>.<quantity>.<direction>``."""

    name: str
    unit: str
    body: str | None = None
    point: str | None = None
    quantity: str | None = None
    direction: str | None = None
    position: list[float] | None = Field(
        None, description="x, y, z of the channel's recorded point (m, see point_frame); "
        "null for channels that are not at a recorded point (wheel forces, body coordinates)")


class PointInfo(BaseModel):
    """A recorded point: its body, name, description, position (m, see ``point_frame``) and
    whether it is on the car-body floor.
    """

    body: str = Field(description="Body the point is on: carbody, frame1, wheelset3...")
    name: str = Field(description="Point name: PR, PC, F3_2 (floor grid), centre...")
    description: str = Field("", description="What the point is, for people")
    x: float = Field(description="Longitudinal position from the car-body centre, forward (m)")
    y: float = Field(description="Lateral position, left positive (m)")
    z: float = Field(description="Height above top of rail (m)")
    on_floor: bool | None = Field(None, description="On the car-body floor (ISO 2631 floor "
                                  "measurement); null off the car body")
    kind: str = Field("", description="paper (one of the paper's points), user, grid (floor "
                      "grid of comfort maps) or body (centre of a frame or wheelset); empty in "
                      "old result files")


class PaperPointOut(BaseModel):
    """One of the paper's car-body measurement points and where it sits."""

    name: str
    description: str
    along: Literal["front", "centre", "rear"] = Field(
        description="Above the front bogie centre, at the body centre or above the rear bogie")
    across: Literal["centre", "left", "right"] = Field(
        description="On the centre line or above the left/right air spring")
    level: Literal["floor", "roof"]


class ChannelList(BaseModel):
    """The channels of a job's results, its sampling and its recorded points."""

    job_id: str
    sample_rate_hz: float
    n_samples: int
    t_start_s: float
    t_end_s: float
    channels: list[ChannelInfo]
    points: list[PointInfo] = Field(
        default_factory=list, description="Recorded points in channel order (m)")
    point_frame: str = Field(description="Coordinates of the point positions")


class SeriesChannel(BaseModel):
    """One channel, decimated: sample times (s) and values."""

    name: str
    unit: str
    time: list[float]
    values: list[float | None]
    distance: list[float] | None = Field(None, description="Distance (m), if asked for")


class SeriesOut(BaseModel):
    """Decimated time series of chosen channels."""

    job_id: str
    method: Literal["minmax", "lttb", "none"]
    max_points: int
    n_samples: int = Field(description="Samples in the requested time range")
    decimated: bool
    sample_rate_hz: float
    channels: list[SeriesChannel]


class PeakOut(BaseModel):
    """A spectral peak."""

    frequency: float
    amplitude: float | None
    value: float | None
    prominence: float | None


class SpectrumChannel(BaseModel):
    """Spectrum values of one channel (on the shared frequency axis)."""

    name: str
    unit: str
    values: list[float | None]
    peaks: list[PeakOut] = Field(default_factory=list)


class SpectrumOut(BaseModel):
    """Amplitude spectrum or PSD of chosen channels."""

    job_id: str
    kind: Literal["amplitude", "psd"]
    frequencies: list[float]
    resolution_hz: float
    window: str
    n_averages: int
    scaling: str
    dynamic: bool = Field(description="Quasi-static part (< 0.3 Hz) removed first")
    decimated: bool
    channels: list[SpectrumChannel]


class SpectrogramOut(BaseModel):
    """Short-time spectrum of one channel: ``values[i_frequency][i_time]``."""

    job_id: str
    channel: str
    unit: str
    times: list[float]
    frequencies: list[float]
    values: list[list[float | None]]
    scaling: str
    window_s: float
    hop_s: float
    resolution_hz: float
    method: str
    dynamic: bool


class SperlingBand(BaseModel):
    """Contribution of a frequency band to the Sperling index."""

    f_low_hz: float
    f_high_hz: float
    w: float | None = Field(description="(Σ W_i^10)^(1/10) over the band's lines")


class SperlingChannel(BaseModel):
    """Sperling index of one channel and its breakdown over frequency."""

    name: str
    direction: Literal["vertical", "lateral"]
    value: float | None = Field(description="Spectral form (default), as in the summary")
    grade: str
    filter_value: float | None = Field(None, description="Filter form, for comparison")
    frequencies: list[float] = Field(
        description="Frequency of each sine (spectral peak) the index sums over (Hz)")
    line_amplitudes: list[float | None] = Field(
        description="Peak amplitude of each of those sines (m/s²)")
    line_w: list[float | None] = Field(description="W_i of each of those sines (-)")
    bands: list[SperlingBand]
    segment_values: list[float | None]
    method: str


class SperlingOut(BaseModel):
    """Sperling breakdown of chosen channels."""

    job_id: str
    dynamic: bool
    channels: list[SperlingChannel]


class CorrelationChannel(BaseModel):
    """Cross-correlation of the reference with one channel."""

    name: str
    lag_at_max_s: float | None
    lag_at_max_interpolated_s: float | None
    value_at_max: float | None
    normalised_at_max: float | None
    local_maxima: list[dict[str, float | None]]
    lags_s: list[float]
    normalised: list[float | None]


class CorrelationOut(BaseModel):
    """Cross-correlations; a maximum at lag > 0 means the channel lags the reference."""

    job_id: str
    reference: str
    max_lag_s: float
    convention: str
    dynamic: bool
    channels: list[CorrelationChannel]
