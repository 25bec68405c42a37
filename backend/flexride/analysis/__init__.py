"""Analysis of car-body vibration and running safety: pure, vectorised functions of arrays and a
sample rate (independent of the solver), and :func:`analyze`, the bridge to a run's
:class:`~flexride.results.Results`.

Modules (definitions, defaults and standard editions in ``docs/analysis.md``):

* :mod:`~flexride.analysis.weighting` — ISO 2631 / EN 12299 weightings Wk, Wd, Wb and Sperling's
  B filters from their analogue definitions, realised digitally;
* :mod:`~flexride.analysis.sperling` — Sperling ride index, spectral and filter form, GB 5599
  grades;
* :mod:`~flexride.analysis.iso2631` — rms, weighted rms, running rms, MTVV, VDV, crest factor,
  comfort bands;
* :mod:`~flexride.analysis.en12299` — continuous comfort C_c and mean comfort N_MV;
* :mod:`~flexride.analysis.spectra` — amplitude spectrum, Welch PSD, dominant peaks;
* :mod:`~flexride.analysis.timefreq` — STFT spectrogram, Morlet scalogram;
* :mod:`~flexride.analysis.correlation` — cross-correlation, lag of the maximum, local maxima;
* :mod:`~flexride.analysis.statistics` — peak statistics, regression against speed;
* :mod:`~flexride.analysis.quasistatic` — quasi-static / dynamic split on curves;
* :mod:`~flexride.analysis.safety` — Y/Q, ΔQ/Q, ΣY (EN 14363 names) with their limits;
* :mod:`~flexride.analysis.comfort_map` — a comfort measure over thousands of nodes;
* :mod:`~flexride.analysis.pipeline` — :func:`analyze`, every analysis of a run;
* :mod:`~flexride.analysis.summary` — :class:`Summary`, what :func:`analyze` returns (JSON form);
* :mod:`~flexride.analysis.tables` — rich tables of a summary;
* :mod:`~flexride.analysis.regression` — a summary quantity against speed over several runs.
"""

from __future__ import annotations

from flexride.analysis.comfort_map import MEASURES, ComfortMap, comfort_map
from flexride.analysis.correlation import CrossCorrelation, cross_correlation, cross_correlations
from flexride.analysis.en12299 import (
    CC_SCALE,
    NMV_SCALE,
    ContinuousComfort,
    MeanComfort,
    cc_scale,
    continuous_comfort,
    mean_comfort,
    nmv_scale,
)
from flexride.analysis.iso2631 import (
    ISO2631_BANDS,
    Iso2631Result,
    WeightedRms,
    comfort_band,
    crest_factor,
    iso2631_comfort,
    mtvv,
    rms,
    running_rms,
    vdv,
    vibration_total_value,
    weighted_rms,
)
from flexride.analysis.pipeline import analyze
from flexride.analysis.quasistatic import (
    QUASISTATIC_DEFAULTS,
    QuasiStaticSplit,
    remove_quasistatic,
    split_quasistatic,
)
from flexride.analysis.regression import regress_summaries
from flexride.analysis.safety import (
    SAFETY_DEFAULTS,
    SAFETY_LIMITS,
    SAFETY_SYMBOLS,
    RunningSafety,
    SafetyIndex,
    derailment_coefficient,
    lateral_force_limit,
    running_safety,
    wheel_unloading,
    wheelset_lateral_force,
)
from flexride.analysis.spectra import (
    SpectralPeak,
    Spectrum,
    amplitude_spectrum,
    dominant_peaks,
    welch_psd,
)
from flexride.analysis.sperling import (
    DEFAULT_SPERLING_FORM,
    SPERLING_DEFAULTS,
    SperlingResult,
    frequency_correction,
    sperling,
    sperling_filter,
    sperling_grade,
    sperling_sine,
    sperling_spectral,
    sperling_total,
)
from flexride.analysis.statistics import (
    LinearFit,
    PeakStats,
    linear_regression,
    peak_statistics,
    regress_on_speed,
)
from flexride.analysis.summary import (
    CorrelationSummary,
    DirectionSummary,
    PointSummary,
    Summary,
)
from flexride.analysis.tables import safety_table, summary_table
from flexride.analysis.timefreq import Scalogram, Spectrogram, scalogram, spectrogram
from flexride.analysis.weighting import (
    WEIGHTINGS,
    WeightingDef,
    apply_weighting,
    weighting_response,
    weighting_sos,
    weighting_zpk,
)

__all__ = [
    "CC_SCALE",
    "DEFAULT_SPERLING_FORM",
    "ISO2631_BANDS",
    "MEASURES",
    "NMV_SCALE",
    "QUASISTATIC_DEFAULTS",
    "SAFETY_DEFAULTS",
    "SAFETY_LIMITS",
    "SAFETY_SYMBOLS",
    "SPERLING_DEFAULTS",
    "WEIGHTINGS",
    "ComfortMap",
    "ContinuousComfort",
    "CorrelationSummary",
    "CrossCorrelation",
    "DirectionSummary",
    "Iso2631Result",
    "LinearFit",
    "MeanComfort",
    "PeakStats",
    "PointSummary",
    "QuasiStaticSplit",
    "RunningSafety",
    "SafetyIndex",
    "Scalogram",
    "SpectralPeak",
    "Spectrogram",
    "Spectrum",
    "SperlingResult",
    "Summary",
    "WeightedRms",
    "WeightingDef",
    "amplitude_spectrum",
    "analyze",
    "apply_weighting",
    "cc_scale",
    "comfort_band",
    "comfort_map",
    "continuous_comfort",
    "crest_factor",
    "cross_correlation",
    "cross_correlations",
    "derailment_coefficient",
    "dominant_peaks",
    "frequency_correction",
    "iso2631_comfort",
    "lateral_force_limit",
    "linear_regression",
    "mean_comfort",
    "mtvv",
    "nmv_scale",
    "peak_statistics",
    "regress_on_speed",
    "regress_summaries",
    "remove_quasistatic",
    "rms",
    "running_rms",
    "running_safety",
    "safety_table",
    "scalogram",
    "spectrogram",
    "sperling",
    "sperling_filter",
    "sperling_grade",
    "sperling_sine",
    "sperling_spectral",
    "sperling_total",
    "split_quasistatic",
    "summary_table",
    "vdv",
    "vibration_total_value",
    "weighted_rms",
    "weighting_response",
    "weighting_sos",
    "weighting_zpk",
    "welch_psd",
    "wheel_unloading",
    "wheelset_lateral_force",
]
