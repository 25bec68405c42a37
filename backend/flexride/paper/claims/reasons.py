"""Why flexride may differ from the paper, with flexride's documented measurements: the notes
of the claims. Each names the input the paper does not give or the modelling difference, and
where flexride documents it.
"""

from __future__ import annotations

TABLE1_CALIBRATED = (
    "flexride's default FE car body was calibrated to these six frequencies (docs/fem.md, "
    "'Calibration to paper Table 1'): an input of the model, not a prediction. The paper does "
    "not give the mode shapes; the mode types are flexride's classification.")

TABLE1_MISSED = (
    "The default car body is calibrated to Table 1 at 0.2 m elements (docs/fem.md); another "
    "mesh (e.g. a coarse test mesh) shifts the frequencies by a few per cent.")

MODE_SHAPES = (
    "The paper gives Table 1's frequencies but not the mode shapes. flexride's car body, "
    "calibrated to those frequencies, has the antinodes of its lowest modes at mid-floor, "
    "excited through the air springs, so the floor centre (PC) moves more than the points above "
    "the bogies (docs/fem.md, 'Floor centre vs above the bogies': rms PC 0.189 vs PFB 0.150 "
    "m/s² at 80 km/h; a stiffer body makes PC ≈ PFB but no longer matches Table 1). Not tuned.")

FLEXIBLE_GAIN = (
    "flexride's flexible car body raises the vibration far more than the paper's few per cent: "
    "the frequency-domain estimate gives a_w (Wb) at PC 0.045 → 0.129 m/s² (+186 %), with "
    "elastic modes at 7.8 and 10.6 Hz carrying about half of the weighted variance "
    "(docs/analysis.md, 'Rigid vs flexible car body'). The difference lies in the car body's "
    "FE model — mode shapes and damping the paper does not give (docs/fem.md) — not in the "
    "solver.")

LATERAL_INPUTS = (
    "The lateral level depends on inputs the paper does not give: the wheel/rail profiles "
    "(LM/CHN60; flexride's presets use a conical tread of conicity 0.05), the lateral fastener "
    "stiffness, the alignment level, lateral or yaw dampers, and the centre-of-gravity heights "
    "(assumed: car body 1.50 m, frame 0.65 m). docs/model.md, 'Real profiles on the paper's "
    "case': lateral Sperling at PC 1.69 (cone) to 2.06 (S1002/60E1) at 80 km/h, rigid, "
    "against the paper's 1.45. None of them was tuned.")

VERTICAL_LEVEL = (
    "The vertical level depends on the irregularity sample and band (the paper names the "
    "German high-disturbance spectrum only; flexride: wavelengths 1–120 m, seed 1) and on "
    "assumed geometry (CG heights, bogie spacing: presets). One 18 s run scatters by about "
    "±10 % in rms (docs/analysis.md, 'Against the time-domain solver'); use --seeds N.")

RMS_INDEX = (
    "The paper does not define its 'RMS index'. Its values (1.6–1.8) have no unit and lie on "
    "the Sperling scale, and no rms acceleration of this vehicle is near 1.6 m/s², so flexride "
    "reads it as Sperling's rms-based form, W = 4.42·a_B^0.3 with a_B the rms of the "
    "B-weighted acceleration (the filter form, DESIGN §6), and reports that; the plain rms "
    "(m/s²) is given beside it. This is a reading, not the paper's definition.")

TABLE2_DIFF = (
    "The paper's difference column does not follow from its own values (1.76/1.71 is +2.9 %, "
    "not +3.5 %; 1.46/1.45 is +0.7 %, not +4.1 %). " + FLEXIBLE_GAIN)

LATERAL_MODE = (
    "flexride's car body sways on its suspension near 1.0 Hz with the conical tread "
    "(docs/model.md, 'Real profiles on the paper's case': lateral/roll mode 1.00 Hz, ζ = 0.26; "
    "1.77 Hz with S1002/60E1), but its flexible body adds elastic lateral motion at the "
    "measured points (rhombic and side-wall modes of Table 1's band: docs/fem.md).")

HIGH_MODE = (
    "flexride keeps elastic modes up to the run's cut-off; the paper's 89.2 Hz roof mode is a "
    "local panel mode of its detailed ANSYS shell model, which flexride's one-layer equivalent "
    "shell (docs/fem.md, 'Known limitations') does not resolve individually.")

PEAK_FREQUENCIES = (
    "Which elastic modes show at PR depends on the mode shapes, which the paper does not give "
    "(docs/fem.md): flexride's modes near 5–10 Hz are breathing, floor, rhombic and roof modes "
    "(Table 1 row), matched to the paper's frequencies but not to its shapes.")

BOGIE_SPACING = (
    "The lag is the time the vehicle needs for the bogie spacing: 12.6 m / 22.2 m/s = 0.567 s "
    "at 80 km/h (DESIGN §5; flexride assumes 12.6 m, the paper does not give it). A short or "
    "single record blurs the maximum between neighbouring peaks of the correlation.")

CURVE_FLANGE = (
    "On the R = 800 m curve the conical tread (conicity 0.05) cannot steer the wheelsets: the "
    "leading wheelsets run 8.1 mm off centre against the 8 mm flangeway, i.e. on the flange "
    "(docs/analysis.md, 'Open points'), which adds lateral shocks the paper's LM tread would "
    "not make. " + LATERAL_INPUTS)

CORRUGATION = (
    "The paper's corrugation ('0.5 mm wavelength, 1 mm depth') is read as 0.5 m wavelength "
    "(presets; docs/model.md, 'Excitation'): 28–44 Hz at 50–80 km/h, far above the suspension "
    "modes, so the response is decided by the elastic modes near that frequency, which the "
    "paper does not describe. With modes kept to 70 Hz (the report's cut-off rule) the 44 Hz "
    "line at 80 km/h meets dense local car-body modes and the frame's vertical bending "
    "(46.6 Hz), 2 % damped: vertical peak at PFB 4.5 m/s² against 0.42 m/s² with modes to "
    "40 Hz (car body alone to 70 Hz: 0.93, frames alone: 2.2; docs/paper.md). The spectral "
    "Sperling index's 5 s rectangular segments leak such a strong line above the 0.5–40 Hz "
    "band into the low lines (amplitude ∝ 1/f from the jump at the segment ends), so the "
    "spectral index under corrugation at 80 km/h mostly measures that leakage.")

SETTLEMENT = (
    "The settlement is one 20 m cosine of 10 cm (paper §4); the response is a transient of the "
    "rigid suspension modes, so the peak is nearly proportional to the speed squared over the "
    "dip's time scale — the paper's fit may cover a narrower response range.")

SPERLING_FORM = (
    "flexride's Sperling index is the spectral form of GB 5599 with 5 s segments and power "
    "averaging (docs/analysis.md, 'Sperling ride index'); the paper does not say which form or "
    "segment length it used (the filter form is about 20 % higher for broadband vibration).")

SINGLE_SAMPLE = (
    "One irregularity realisation per condition makes trends over 10 km/h steps noisy (single "
    "values scatter by several per cent, docs/model.md); run --seeds N for confidence "
    "intervals.")

QUICK = "In a --quick study the runs are short and only two speeds are run."

MESH_GROWTH = (
    "flexride starts every run from the static equilibrium of the flexible vehicle, and every "
    "mesh carries the same mass, centre of gravity and inertias (docs/fem.md): on the smooth "
    "track each air spring carries its static 86.9 kN on every mesh from 0.1 to 0.5 m, and the "
    "dynamic part (discrete rail support, 37 Hz at 80 km/h) is about 2 N, 10⁻⁵ of it, "
    "unchanged by the mesh (docs/fem.md, 'The response against element size'). The paper "
    "does not say how its runs start or what its Fig. 4 plots (a largest value, an rms, a "
    "transient); a force that grows with coarser elements would need a run that does not "
    "start in equilibrium, so that the coarser, softer body swings further — not verified.")

MESH_ADEQUATE = (
    "Judged on the converged estimates of the three finest meshes (0.1, 0.15, 0.2 m: "
    "Richardson's value where they converge monotonically at an order of at least 0.5, else "
    "the finest mesh's value; Celik et al. 2008, Eça and Hoekstra 2014; docs/fem.md 'The "
    "response against element size'). The meshes are not refinements of each other, so "
    "quantities that hang on the floor panels' modes (the vertical rms at the floor centre) "
    "move by a few per cent between meshes. The paper's own criterion for 'adequate' is not "
    "stated; flexride's is 5 % of every quantity.")
