"""Named scenarios: the paper's vehicle and track (``paper-metro``) and its 16 conditions.

Paper values (Table 4, vehicle; Table 5, track) are used as printed. What the paper does not
give is filled with typical B-type metro values, stated here and in ``docs/model.md``:

* car body 19.0 m long, 2.8 m wide, floor 1.10 m and roof 3.80 m above top of rail (TOR);
* bogie centre spacing 12.6 m, wheelbase 2.2 m, wheel radius 0.42 m, half distance between
  rolling circles 0.7465 m; primary springs ±1.0 m and air springs ±0.95 m laterally;
* centre-of-gravity heights above TOR: car body 1.50 m, bogie frame 0.65 m, wheelset 0.42 m
  (axle centre); primary springs act 0.50 m and air springs 0.90 m above TOR;
* CHN60 rail: I_z = 5.24e-6 m⁴, torsion constant 2.35e-6 m⁴ (G·J = 1.9e5 N·m²), polar moment
  3.741e-5 m⁴; the paper's single fastener stiffness/damping (30 MN/m, 10 kN·s/m) is used for the
  vertical and the lateral direction;
* wheel–rail profiles: S1002 wheels (EN 13715) on 60E1 rails (EN 13674-1) at 1:40, flange
  backs 1.36 m, as a substitute for the paper's LM tread and CHN60 rail, which are not openly
  published (users load theirs from files); friction 0.3. The time step is ``auto`` (the
  default): the solver chooses it from the stability limit of its one-step map
  (:mod:`flexride.solver.stability`; 1/16000 s for these profiles); the conical tread of the
  first releases is :data:`CONICAL_TREAD`;
* German high-disturbance random irregularity, wavelengths 1–120 m, all four components;
* corrugation: the paper prints "wavelength 0.5 mm, depth 1 mm", which is shorter than the
  contact patch and cannot be meant; read as 0.5 m wavelength, 1 mm depth (peak to peak);
* settlement: one cosine dip, 20 m wavelength, 10 cm depth;
* curve: R = 800 m, 55 m transitions, 95 mm superelevation, 200 m arc (arc length assumed).
"""

from __future__ import annotations

from typing import Any

from flexride.errors import UnknownPresetError
from flexride.scenario.scenario import Scenario, apply_overrides, scenario_from_dict

PAPER_SPEEDS_KMH = (50, 60, 70, 80)

PAPER_VEHICLE: dict[str, Any] = {
    "carbody": {
        "mass": 35443.0,
        "ixx": 50929.0,
        "iyy": 1410960.0,
        "izz": 1401490.0,
        "cg_height": 1.50,
    },
    "frame": {"mass": 4007.0, "ixx": 1194.0, "iyy": 876.0, "izz": 2099.0, "cg_height": 0.65},
    "wheelset": {"mass": 1878.0, "ixx": 1055.0, "iyy": 139.0, "izz": 1055.0, "cg_height": 0.42},
    "geometry": {
        "bogie_centre_spacing": 12.6,
        "wheelbase": 2.2,
        "wheel_radius": 0.42,
        "rolling_circle_half_distance": 0.7465,
        "primary_lateral_half_spacing": 1.0,
        "primary_height": 0.50,
        "secondary_lateral_half_spacing": 0.95,
        "secondary_height": 0.90,
    },
    "primary": {"kx": 7.0e6, "ky": 4.0e6, "kz": 0.9e6, "cx": 1.0e4, "cy": 1.0e4, "cz": 1.0e4},
    "secondary": {
        "kx": 220.1e3,
        "ky": 220.1e3,
        "kz": 341.9e3,
        "cx": 6.0e4,
        "cy": 6.0e4,
        "cz": 8.0e4,
    },
}

PAPER_CONTACT: dict[str, Any] = {"geometry": "profiles", "flange_back_distance": 1.36}
"""Contact of the paper presets: S1002 on 60E1 at 1:40 (the contact defaults) with the EN
flange-back distance (m)."""

PAPER_TRACK: dict[str, Any] = {
    "rail": {"area": 7.745e-3, "youngs_modulus": 2.1e11, "iy": 3.214e-5},
    "fastener": {"spacing": 0.6, "kz": 3.0e7, "cz": 1.0e4, "ky": 3.0e7, "cy": 1.0e4},
}

PAPER_RANDOM = {
    "kind": "random",
    "spectrum": "german-high",
    "wavelength_min_m": 1.0,
    "wavelength_max_m": 120.0,
    "seed": 1,
}
PAPER_CORRUGATION = {"kind": "corrugation", "wavelength_m": 0.5, "depth_m": 0.001, "start_m": 0.0}
PAPER_SETTLEMENT = {"kind": "settlement", "wavelength_m": 20.0, "depth_m": 0.10, "position_m": 40.0}
PAPER_CURVE = {
    "kind": "curve",
    "radius_m": 800.0,
    "direction": "left",
    "superelevation_m": 0.095,
    "entry_transition_m": 55.0,
    "exit_transition_m": 55.0,
    "arc_length_m": 200.0,
    "start_m": 40.0,
}

# condition key -> (description, line, excitation list, distance in m)
PAPER_CONDITIONS: dict[str, tuple[str, dict[str, Any], list[dict[str, Any]], float]] = {
    "random-straight": (
        "Rail random irregularity (German high disturbance), straight track",
        {"kind": "straight"},
        [PAPER_RANDOM],
        400.0,
    ),
    "random-curve": (
        "Rail random irregularity on an R = 800 m curve with 55 m transitions and "
        "95 mm superelevation",
        PAPER_CURVE,
        [PAPER_RANDOM],
        410.0,
    ),
    "corrugation": (
        "Short-wave excitation: corrugation, 0.5 m wavelength, 1 mm depth, straight",
        {"kind": "straight"},
        [PAPER_CORRUGATION],
        200.0,
    ),
    "settlement": (
        "Long-wave excitation: settlement, one cosine of 20 m wavelength and 10 cm depth, straight",
        {"kind": "straight"},
        [PAPER_SETTLEMENT],
        120.0,
    ),
}


SMOOTH_CONDITION = "smooth-straight"
"""The condition of the paper's element-size pre-calculation (§2.1, Fig. 4)."""

# the paper's conditions outside Table 3: same form as PAPER_CONDITIONS
PRECALCULATION_CONDITIONS: dict[str, tuple[str, dict[str, Any], list[dict[str, Any]], float]] = {
    SMOOTH_CONDITION: (
        "Smooth straight track, no irregularity (the paper's element-size pre-calculation, "
        "section 2.1, Fig. 4)",
        {"kind": "straight"},
        [],
        400.0,
    ),
}

STUDY_CONDITIONS = {**PAPER_CONDITIONS, **PRECALCULATION_CONDITIONS}
"""Every named condition a study or the paper report may use."""


def paper_metro(**top_level: Any) -> dict[str, Any]:
    """The ``paper-metro`` base scenario as a dict (straight, smooth track, 80 km/h, 10 s)."""
    data: dict[str, Any] = {
        "name": "paper-metro",
        "description": "Metro vehicle (paper Table 4) on slab track with discrete fasteners "
        "(paper Table 5); geometry not given by the paper from B-type metro values",
        "vehicle": PAPER_VEHICLE,
        "track": PAPER_TRACK,
        "line": {"kind": "straight"},
        "excitation": [],
        "contact": PAPER_CONTACT,
        "speed_kmh": 80.0,
        "duration_s": 10.0,
    }
    data.update(top_level)
    return data


def _paper_condition(key: str, speed: float) -> dict[str, Any]:
    desc, line, exc, distance = STUDY_CONDITIONS[key]
    table = "Paper Table 3" if key in PAPER_CONDITIONS else "Paper"
    return paper_metro(
        name=f"paper-{key}-{speed:g}",
        description=f"{table}: {desc}, {speed:g} km/h",
        line=line,
        excitation=exc,
        speed_kmh=float(speed),
        duration_s=None,
        distance_m=distance,
    )


def _all_presets() -> dict[str, dict[str, Any]]:
    presets = {"paper-metro": paper_metro()}
    presets["paper-metro-random"] = paper_metro(
        name="paper-metro-random",
        excitation=[PAPER_RANDOM],
        description="Reference case of the benchmarks: paper vehicle, straight track, German "
        "high disturbance, 80 km/h, 10 s",
    )
    for key in PAPER_CONDITIONS:
        for speed in PAPER_SPEEDS_KMH:
            p = _paper_condition(key, speed)
            presets[p["name"]] = p
    return presets


PRESETS: dict[str, dict[str, Any]] = _all_presets()

REAL_PROFILES: dict[str, Any] = {f"contact.{k}": v for k, v in PAPER_CONTACT.items()}
"""Overrides that set any scenario up with real profiles as the paper presets are: S1002 on
60E1 at 1:40 and the EN flange-back distance (m)."""

CONICAL_TREAD: dict[str, Any] = {"contact.geometry": "conical"}
"""Overrides that run a paper preset with the conical tread of the first releases
(equivalent conicity 0.05, flange contact as a spring beyond 8 mm): for comparisons with the
cone and with codes that use one."""


def preset_dict(name: str, overrides: dict[str, Any] | None = None) -> dict[str, Any]:
    """The scenario mapping of preset ``name`` with optional dotted-path overrides."""
    if name not in PRESETS:
        raise UnknownPresetError(f"unknown preset {name!r}; available: {', '.join(PRESETS)}")
    data = PRESETS[name]
    return apply_overrides(data, overrides or {})


def load_preset(name: str, overrides: dict[str, Any] | None = None) -> Scenario:
    """Validated :class:`Scenario` of preset ``name`` with optional dotted-path overrides."""
    return scenario_from_dict(preset_dict(name, overrides), source=f"preset {name}")


def load_condition(key: str, speed_kmh: float, overrides: dict[str, Any] | None = None
                   ) -> Scenario:
    """The paper vehicle on condition ``key`` of :data:`STUDY_CONDITIONS` at ``speed_kmh``
    (km/h), with optional dotted-path overrides: the preset ``paper-<key>-<speed>`` for
    Table 3's conditions and speeds, and the same construction for the others.

    Raises
    ------
    UnknownPresetError
        Unknown condition.
    """
    if key not in STUDY_CONDITIONS:
        raise UnknownPresetError(f"unknown condition {key!r}; available: "
                                 f"{', '.join(STUDY_CONDITIONS)}")
    data = apply_overrides(_paper_condition(key, float(speed_kmh)), overrides or {})
    return scenario_from_dict(data, source=f"condition {key} at {speed_kmh:g} km/h")
