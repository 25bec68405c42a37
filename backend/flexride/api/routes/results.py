"""Routes of a job's results: summary, channels, series, spectra, Sperling breakdown,
cross-correlation and the HDF5 download.

Every JSON answer goes through :func:`flexride.api.services.result_cache.cached_answer`: the
job is checked in the database on every request, the rendered answer of a finished job is
kept in memory, keyed by the job, its file and every parameter passed here.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import FileResponse
from pydantic import StringConstraints

from flexride.api.deps import ServicesDep
from flexride.api.params import JobId
from flexride.api.schemas import (
    ChannelList,
    CorrelationOut,
    SeriesOut,
    SpectrogramOut,
    SpectrumOut,
    SperlingOut,
)
from flexride.api.services import results as svc_results
from flexride.api.services.result_cache import cached_answer

router = APIRouter(prefix="/jobs/{job_id}", tags=["results"],
                   responses={409: {"description": "The job has no results (yet)"}})

Channels = Annotated[list[Annotated[str, StringConstraints(min_length=1, max_length=120)]], Query(
    description="Channel names (repeat the parameter), e.g. carbody.PR.acc.z")]
Dynamic = Annotated[bool, Query(
    description="Remove the quasi-static part (< 0.3 Hz) first, as the summary does")]
_MAX_CHANNELS = 16


def _channels(names: list[str]) -> list[str]:
    from flexride.errors import AnalysisError

    if len(names) > _MAX_CHANNELS:
        raise AnalysisError(f"channels: at most {_MAX_CHANNELS} per request")
    for n in names:
        if not 0 < len(n) <= 120:
            raise AnalysisError(f"channels: {n[:40]!r} is not a channel name")
    return names


@router.get("/summary", response_model=dict[str, Any], summary="Comfort summary")
def summary(request: Request, job_id: JobId, svc: ServicesDep) -> Any:
    """Comfort indices (Sperling, ISO 2631, EN 12299), peaks, rms, dominant frequencies per
    point and direction, correlations and running safety (``flexride.analysis.analyze``).
    """
    return cached_answer(request, svc, job_id, "summary", (),
                         lambda: svc_results.summary(svc, job_id), from_file=False)


@router.get("/channels", response_model=ChannelList, summary="Recorded channels")
def channels(request: Request, job_id: JobId, svc: ServicesDep) -> Any:
    """Channel names with units, sample rate and time range."""
    return cached_answer(request, svc, job_id, "channels", (),
                         lambda: svc_results.channel_list(svc, job_id))


@router.get("/series", response_model=SeriesOut, summary="Decimated time series")
def series(
    request: Request,
    job_id: JobId,
    svc: ServicesDep,
    channels: Channels,
    max_points: Annotated[int, Query(ge=10, le=200_000)] = 2000,
    method: Annotated[Literal["minmax", "lttb", "none"], Query(
        description="minmax: min and max of each bucket (peaks kept); lttb: "
        "largest-triangle-three-buckets; none: all samples")] = "minmax",
    t_start: Annotated[float | None, Query(ge=-1e6, le=1e6, description="From (s)")] = None,
    t_end: Annotated[float | None, Query(ge=-1e6, le=1e6, description="To (s)")] = None,
    distance: Annotated[bool, Query(description="Include the distance axis (m)")] = False,
) -> Any:
    """Channels decimated on the server to at most ``max_points`` samples each, with their
    sample times.
    """
    names = _channels(channels)
    return cached_answer(request, svc, job_id, "series",
                         (tuple(names), max_points, method, t_start, t_end, distance),
                         lambda: svc_results.series(svc, job_id, names, max_points, method,
                                                    t_start, t_end, distance))


@router.get("/spectrum", response_model=SpectrumOut, summary="Amplitude spectrum")
def spectrum(
    request: Request,
    job_id: JobId,
    svc: ServicesDep,
    channels: Channels,
    fmax: Annotated[float, Query(gt=0.0, le=1e5, description="Highest frequency (Hz)")] = 100.0,
    dynamic: Dynamic = True,
    max_points: Annotated[int, Query(ge=10, le=200_000)] = 5000,
) -> Any:
    """One-sided peak-amplitude spectrum of the whole record (m/s² per line), with the
    dominant peaks.
    """
    names = _channels(channels)
    return cached_answer(request, svc, job_id, "spectrum",
                         (tuple(names), fmax, dynamic, max_points),
                         lambda: svc_results.spectrum(svc, job_id, names, "amplitude", fmax,
                                                      dynamic, 8.0, max_points))


@router.get("/psd", response_model=SpectrumOut, summary="Power spectral density")
def psd(
    request: Request,
    job_id: JobId,
    svc: ServicesDep,
    channels: Channels,
    fmax: Annotated[float, Query(gt=0.0, le=1e5)] = 100.0,
    segment_s: Annotated[float, Query(gt=0.05, le=600.0,
                                      description="Welch segment length (s)")] = 8.0,
    dynamic: Dynamic = True,
    max_points: Annotated[int, Query(ge=10, le=200_000)] = 5000,
) -> Any:
    """Welch PSD ((m/s²)²/Hz; Hann segments, 50 % overlap) with the dominant peaks."""
    names = _channels(channels)
    return cached_answer(request, svc, job_id, "psd",
                         (tuple(names), fmax, segment_s, dynamic, max_points),
                         lambda: svc_results.spectrum(svc, job_id, names, "psd", fmax, dynamic,
                                                      segment_s, max_points))


@router.get("/spectrogram", response_model=SpectrogramOut, summary="Spectrogram")
def spectrogram(
    request: Request,
    job_id: JobId,
    svc: ServicesDep,
    channel: Annotated[str, Query(min_length=1, max_length=120)],
    window_s: Annotated[float, Query(gt=0.05, le=600.0)] = 2.0,
    overlap: Annotated[float, Query(ge=0.0, lt=1.0)] = 0.75,
    fmax: Annotated[float, Query(gt=0.0, le=1e5)] = 50.0,
    scaling: Annotated[Literal["psd", "magnitude"], Query()] = "psd",
    dynamic: Dynamic = True,
) -> Any:
    """Short-time Fourier transform of one channel (``values[frequency][time]``)."""
    return cached_answer(request, svc, job_id, "spectrogram",
                         (channel, window_s, overlap, fmax, scaling, dynamic),
                         lambda: svc_results.spectrogram_of(svc, job_id, channel, window_s,
                                                            overlap, fmax, dynamic, scaling))


@router.get("/sperling", response_model=SperlingOut, summary="Sperling breakdown")
def sperling(request: Request, job_id: JobId, svc: ServicesDep, channels: Channels,
             dynamic: Dynamic = True) -> Any:
    """Sperling index (spectral form, 5 s segments) with W per spectral line and per
    third-octave band, and the filter form for comparison (records of at least 5 s).
    """
    names = _channels(channels)
    return cached_answer(request, svc, job_id, "sperling", (tuple(names), dynamic),
                         lambda: svc_results.sperling_breakdown(svc, job_id, names, dynamic))


@router.get("/correlation", response_model=CorrelationOut, summary="Cross-correlation")
def correlation(
    request: Request,
    job_id: JobId,
    svc: ServicesDep,
    reference: Annotated[str, Query(min_length=1, max_length=120,
                                    description="Reference channel (a)")],
    channels: Channels,
    max_lag_s: Annotated[float, Query(gt=0.0, le=600.0)] = 3.0,
    dynamic: Dynamic = True,
    max_points: Annotated[int, Query(ge=10, le=200_000)] = 4000,
) -> Any:
    """R_ab(τ) of the reference (a) with each channel (b): a maximum at τ > 0 means b lags
    a; normalised curve, lag and value of the maximum, local maxima.
    """
    names = _channels(channels)
    return cached_answer(request, svc, job_id, "correlation",
                         (reference, tuple(names), max_lag_s, dynamic, max_points),
                         lambda: svc_results.correlation(svc, job_id, reference, names,
                                                         max_lag_s, dynamic, max_points))


@router.get("/download", response_class=FileResponse, summary="Download the HDF5 file",
            responses={200: {"content": {"application/x-hdf5": {}},
                             "description": "The job's results file"}})
def download(job_id: JobId, svc: ServicesDep) -> FileResponse:
    """The whole results file (HDF5, layout in ``flexride.results``)."""
    path, name = svc_results.result_path(svc, job_id)
    return FileResponse(path, media_type="application/x-hdf5", filename=name)
