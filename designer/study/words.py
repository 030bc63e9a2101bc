"""The words for what a study file names by identifier: factors, the draws replicates
re-seed, the results.csv metrics and the costs. A surveyor reads "flight height above
ground (m)", not ``altitude-m``: the Study panel names them so (the identifier in the
tooltip, it is what the study file and results.csv say), and ``designer study check``
names them so with the identifier after them, in parentheses (:func:`named`). Every
identifier has its words here: a test walks the lists of :mod:`designer.study`."""

from __future__ import annotations

import re

#: factors of :data:`designer.study.factors.FACTORS`
FACTOR_WORDS = {
    "altitude-m": "flight height above ground (m)",
    "gsd-m": "ground sample distance (m per pixel)",
    "flight-geometry": "flight pattern (nadir, crosshatch or tilted)",
    "pose-noise-sigma-m": "flown position error σ (m)",
    "pose-noise-sigma-deg": "flown attitude error σ (°)",
    "control-count": "number of control GCPs",
    "gcp-survey-sigma-m": "GCP survey error σ (m)",
    "position-prior-sigma-m": "measured camera position error σ (m)",
    "k1": "lens distortion k1",
    "k2": "lens distortion k2",
    "sensor-noise-dn": "sensor noise σ (DN)",
    "sun-elevation-deg": "sun elevation (°)",
    "cloud-cover": "cloud cover (share of the ground)",
    "takeoff-time": "take-off time (UTC)",
    "moving-object-speed-m-s": "speed of the moving objects (m/s)",
    "oblique-tilt-deg": "oblique camera tilt (°)",
    "rolling-shutter-readout-s": "rolling-shutter readout time (s)",
    "building-eave-height-m": "building wall height (m)",
    "vegetation-density-per-m2": "plant density (per m²)",
    "vegetation-wind-amplitude-deg": "plants swaying in the wind (°)",
    "texture-file": "ground texture image",
    "texture-variation-strength": "ground texture variation (0 to 1)",
    "render-preset": "render quality",
    "render-samples": "render samples per pixel",
    "cloud-size-m": "cloud shadow size (m)",
    "cloud-depth": "cloud shadow darkness (0 to 1)",
    "wind-speed-m-s": "cloud drift speed (m/s)",
    "wind-direction-deg": "cloud drift direction (°)",
    "flight-camera": "camera or rig flown",
    "front-overlap-percent": "front overlap (%)",
    "side-overlap-percent": "side overlap (%)",
    "crosshatch": "crosshatch (a second grid at 90°)",
    "flight-speed-m-s": "flight speed (m/s)",
    "turn-s": "time per turn between lines (s)",
    "jpeg-quality": "JPEG quality",
    "exposure-sigma-ev": "exposure error σ (EV)",
    "white-balance-sigma-k": "white-balance error σ (K)",
    "chromatic-aberration-red-ppm": "chromatic aberration, red (ppm)",
    "chromatic-aberration-blue-ppm": "chromatic aberration, blue (ppm)",
    "calibration": "camera parameters the adjustment estimates",
    "rolling-shutter-processing": "rolling-shutter processing",
    "pre-calibration-focal-px": "starting focal length error σ (px)",
    "pre-calibration-k1": "starting k1 error σ",
    "gcp-mode": "how the GCPs enter the adjustment",
    "marking-sigma-px": "GCP marking error σ (px)",
    "control-spread": "how the control GCPs are chosen",
    "position-prior": "camera positions measured in flight",
    "max-features": "SIFT features per image",
    "mapper": "structure-from-motion mapper",
}

#: draws of :data:`designer.study.factors.DRAWS` a replicate re-seeds
DRAW_WORDS = {  # short: two columns of them fit the panel's width
    "gcp-selection": "control GCPs chosen",
    "clouds": "cloud shadows",
    "survey-error": "GCP survey error",
    "pose-noise": "flown poses",
    "sensor-noise": "sensor noise",
    "exposure-variation": "exposure errors",
    "pre-calibration": "calibration error",
    "marking-error": "GCP marking error",
    "position-prior": "GNSS positions",
}

#: the stages a factor belongs to, as the panel says them
STAGE_WORDS = {"render": "render", "processing": "processing"}

#: results.csv columns (:data:`designer.study.results.METRIC_COLUMNS`) not worded by
#: :func:`metric_words`' patterns
_METRIC_WORDS = {
    "registered": "images registered",
    "images": "images per survey",
    "gsd_m": "GSD (m)",
    "dome_amplitude_m": "dome (bowl) amplitude (m)",
    "dome_amplitude_gsd": "dome (bowl) amplitude (GSD)",
    "sparse_dome_gsd": "tie-point dome (bowl) amplitude (GSD)",
    "k1_error_beyond_focal": "k1 error beyond the focal trade",
    "focal_error_px": "focal length error (px)",
    "k1_error": "k1 error",
    "render_s": "render time (s)",
    "reconstruct_s": "reconstruction time (s)",
    "compare_s": "comparison time (s)",
    "total_s": "time per run (s)",
    "amortised_s": "time per run, shared work divided (s)",
    "flight_min": "flight time (min)",
    "gcps": "GCP targets surveyed",
    "control_gcps": "control GCPs",
    "render_cpu_s": "render CPU time (s)",
    "reconstruct_cpu_s": "reconstruction CPU time (s)",
    "compare_cpu_s": "comparison CPU time (s)",
    "cpu_s": "CPU time per run (s)",
    "cpu_amortised_s": "CPU time per run, shared work divided (s)",
}
_AXES = {"x": "X", "y": "Y", "z": "Z", "xy": "XY", "xyz": "3D"}
_UNITS = {"m": "m", "gsd": "GSD"}
_STATISTICS = {"median": "median", "nmad": "NMAD", "mean": "mean", "rmse": "RMSE"}
_RMSE = re.compile(r"(check|control)_rmse_(x|y|z|xy|xyz)_(m|gsd)")
_CLOUD = re.compile(r"(dtm_)?cloud_(median|nmad|mean|rmse)_m")


def factor_words(name: str) -> str:
    """'flight height above ground (m)' for ``altitude-m``; a factor not listed here
    takes the words its declaration gives (label and unit), else its description."""
    if name in FACTOR_WORDS:
        return FACTOR_WORDS[name]
    from designer.study.factors import FACTORS

    factor = FACTORS[name]
    return factor.words or factor.doc


def draw_words(name: str) -> str:
    """'which GCPs are control' for ``gcp-selection``."""
    return DRAW_WORDS[name]


def metric_words(column: str) -> str:
    """'check-point RMSE XY (m)' for ``check_rmse_xy_m``; 'cloud error NMAD (m)',
    'bare-ground cloud error median (m)' for the cloud's (DSM) and the bare earth's."""
    if column in _METRIC_WORDS:
        return _METRIC_WORDS[column]
    rmse = _RMSE.fullmatch(column)
    if rmse:
        who, axis, unit = rmse.groups()
        return f"{who}-point RMSE {_AXES[axis]} ({_UNITS[unit]})"
    cloud = _CLOUD.fullmatch(column)
    if cloud:
        bare, statistic = cloud.groups()
        what = "bare-ground cloud error" if bare else "cloud error"
        return f"{what} {_STATISTICS[statistic]} (m)"
    raise KeyError(column)


def named(words: str, identifier: str) -> str:
    """``“flight height above ground (m)” (altitude-m)``: the words, then what the study
    file writes, for a line of the command line."""
    return f"“{words}” ({identifier})"


def tip(words_doc: str, identifier: str) -> str:
    """A tooltip: the explanation, then the identifier the study file uses."""
    return f"{words_doc}\n(in the study file: {identifier})"
