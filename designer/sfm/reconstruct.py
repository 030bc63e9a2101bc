"""Reconstruct a rendered survey with COLMAP (pycolmap) as a practitioner processes it.

Input: an output folder of ``designer render`` (``images/`` + ``ground-truth/``); the
processing settings are the project's ``<processing>`` (designer.sfm.settings) with
command-line overrides. Modes:

* ``known-poses`` — the ideal case: SIFT features and matches, then triangulation with
  the true interior and exterior orientations (nothing is estimated but points);
* ``free`` — incremental SfM from the images (starting from the pre-calibration), a
  track-length filter, a first datum (camera-position priors or a similarity on the
  control points), then the final bundle adjustment (designer.sfm.adjustment): control
  points and camera positions as weighted observations, the interior orientation
  estimated as the calibration mode says. With ``gcps = similarity`` a 7-parameter
  similarity on the control points follows the adjustment instead.

Several cameras (a rig, or flights with different cameras): each ground-truth CAMERA_ID
is its own database camera with its own interior orientation (true in ``known-poses``,
its own pre-calibration and self-calibration in ``free``). In ``free`` mode a rig of the
project is a COLMAP rig (designer.sfm.rigs): one database camera per mount (its own
self-calibration), one frame per station, the mounts' relative orientation fixed at the
project's values, so a station has one pose.

Check points are marked (with the same marking error) but only triangulated with the
final cameras, never used. Everything is computed in a local frame (world − offset,
offset = the rounded mean camera centre) in float64; outputs are in world coordinates:
``summary.json``, ``sparse.ply`` (= ``cloud.ply``, doubles), ``gcp_residuals.csv``,
``model/`` (COLMAP text model). Dense matching is another stage (``dense`` setting).

The steps, each in the module of its concern: the survey read (designer.sfm.inputs),
features and matches (designer.sfm.features), cameras and tie points
(designer.sfm.mapping), the tie-point filters around georeferencing and the adjustment
(designer.sfm.tie_points, designer.sfm.process_free), results and files
(designer.sfm.results), the tie-point dome (designer.sfm.dome) and the dense stage
(designer.sfm.dense_stage).
"""

from __future__ import annotations

import contextlib
import json
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from designer.atomic import write_text_atomic
from designer.project import model as m
from designer.sfm.dense_stage import with_dense_stage
from designer.sfm.dome import tie_point_dome
from designer.sfm.feature_cache import FeatureCache
from designer.sfm.features import extract_features, match_features
from designer.sfm.inputs import MODES, read_inputs
from designer.sfm.mapping import apply_rigs, map_cameras
from designer.sfm.results import evaluate_block, gsd_m, summary_of, write_model
from designer.sfm.settings import project_of_survey
from designer.sfm.tie_points import filter_and_adjust

__all__ = ["MODES", "ReconstructionResult", "reconstruct"]


@dataclass(frozen=True)
class ReconstructionResult:
    out_dir: Path
    mode: str
    n_images: int
    n_registered: int
    n_points: int
    cloud_ply: Path
    gcp_residuals_csv: Path
    summary: dict


def _log_default(message: str) -> None:
    print(message, flush=True)


@contextlib.contextmanager
def _timed(timings: dict[str, float], name: str, cpu: dict[str, float]) -> Iterator[None]:
    """``timings[name]``: the wall seconds the block took, ``cpu[name]`` this process's
    CPU seconds in it (all threads), when it finishes."""
    t, c = time.perf_counter(), time.process_time()
    yield
    timings[name] = time.perf_counter() - t
    cpu[name] = time.process_time() - c


def reconstruct(
    survey_dir: Path,
    out_dir: Path,
    mode: str = "known-poses",
    max_features: int | None = None,
    log: Callable[[str], None] = _log_default,
    processing: m.Processing | None = None,
    project_path: Path | None = None,
    dense_max_image_px: int | None = None,
    feature_cache: Path | None = None,
    rigs: list | None = None,
) -> ReconstructionResult:
    """Features, matching, SfM or triangulation, adjustment; write model, cloud, report;
    with ``dense`` on, the dense cloud, DSM and DEM of difference (designer.sfm.dense_stage;
    ``project_path`` gives the true surface, default: the project the survey names).
    ``feature_cache``: a folder where features and matches are kept and reused by
    reconstructions of the same images (designer.sfm.feature_cache). ``rigs``: the
    designer.sfm.rigs.ProcessingRig list whose relative orientation ``free`` mode fixes
    (default: the rigs of the project, when it is found)."""
    survey, out = Path(survey_dir), Path(out_dir)
    inputs = read_inputs(survey, mode, processing or m.Processing(), max_features, log)
    out.mkdir(parents=True, exist_ok=True)
    cache = FeatureCache(feature_cache) if feature_cache is not None else None
    timings: dict[str, float] = {}
    cpu: dict[str, float] = {}  # the same stages' CPU seconds
    with _timed(timings, "features_s", cpu):
        features = extract_features(inputs, out / "database.db", cache, log)
    with _timed(timings, "matching_s", cpu):
        matches = match_features(inputs, features, out, cache, log)
    layout = apply_rigs(features.db_path, inputs.cams, rigs, project_path, survey, log) \
        if mode == "free" else None
    with _timed(timings, "reconstruction_s", cpu):
        mapped = map_cameras(inputs, features, matches, layout, out / "sparse", cache, log)
    rec = mapped.rec
    with _timed(timings, "adjustment_s", cpu):
        block = filter_and_adjust(rec, inputs, log)
    evaluated = evaluate_block(rec, inputs, block, layout)
    written = write_model(rec, inputs.offset, evaluated.rows, out)  # rec now world frame
    reused = {"features": features.reused, "matches": matches.reused,
              **({} if mapped.reused is None else {"sfm": mapped.reused})}
    summary = summary_of(rec, inputs, evaluated, block, layout, matches, reused, timings)
    summary["stage_cpu_seconds"] = cpu
    truth_project = project_path or project_of_survey(survey)
    survey_gsd_m = gsd_m(inputs, rec)
    summary["sparse_dome"] = tie_point_dome(rec, truth_project, survey_gsd_m, log)
    if inputs.processing.dense != "none":
        summary = with_dense_stage(summary, survey, out, written.model_dir, truth_project,
                                   inputs.offset, survey_gsd_m,
                                   max_image_size_px=dense_max_image_px, log=log)
    write_text_atomic(out / "summary.json", json.dumps(summary, indent=1))
    n_tied, n_points = len(evaluated.tied), rec.num_points3D()
    log(f"{n_tied}/{len(inputs.names)} images registered, {n_points} points")
    return ReconstructionResult(out, mode, len(inputs.names), n_tied, n_points,
                                written.cloud_ply, written.gcp_residuals_csv, summary)
