"""The tie points kept around the adjustment: tracks too short before it, points whose
reprojection error is too large after it; in ``free`` mode the georeferencing and final
adjustment between the two (designer.sfm.process_free)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from designer.sfm.inputs import SurveyInputs

#: tie points whose mean reprojection error exceeds this after the adjustment are outliers
OUTLIER_PX = 4.0


@dataclass(frozen=True)
class AdjustedBlock:
    """What the filters and the adjustment did: ``tie``, the tie-point counts of the
    summary; ``adjustment`` (designer.sfm.adjustment.AdjustmentResult) and
    ``similarity`` (its information), None when not run; ``errors``: point id → the
    reprojection errors of its observations with rolling-shutter compensation, px, or
    None (COLMAP's errors count)."""

    tie: dict
    adjustment: object | None
    similarity: dict | None
    errors: dict | None


def filter_and_adjust(rec, inputs: SurveyInputs, log: Callable[[str], None]) -> AdjustedBlock:
    """Drop the short tracks, georeference and adjust ``rec`` in place (``free`` mode),
    then drop the outliers (:data:`OUTLIER_PX`)."""
    p = inputs.processing
    tie = {"points_before_filters": rec.num_points3D()}
    tie["removed_short_tracks"] = drop_short_tracks(rec, p.matching.min_track_length)
    adjustment = None
    sim_info = None
    if inputs.mode == "free":
        from designer.sfm import process_free

        adjustment, sim_info = process_free.georeference_and_adjust(
            rec, p, inputs.gcps, inputs.marks, inputs.control, inputs.flight_C, inputs.offset,
            log, str(inputs.survey), rolling_shutter=inputs.rolling)
    errors = adjustment.point_errors_px if adjustment is not None else None
    tie["removed_outliers"] = drop_outliers(rec, OUTLIER_PX, errors)
    tie["points"] = rec.num_points3D()
    tie["mean_track_length"] = float(rec.compute_mean_track_length()) if rec.num_points3D() \
        else 0.0
    return AdjustedBlock(tie, adjustment, sim_info, errors)


def drop_short_tracks(rec, min_length: int) -> int:
    """Delete the tie points seen in fewer than ``min_length`` images; how many."""
    short = [pid for pid, pt in rec.points3D.items() if pt.track.length() < min_length]
    for pid in short:
        rec.delete_point3D(pid)
    return len(short)


def drop_outliers(rec, max_px: float, errors: dict | None = None) -> int:
    """Delete the tie points whose mean reprojection error exceeds ``max_px``: COLMAP's
    errors, or with rolling-shutter compensation ``errors`` (point id → the errors of its
    observations with the compensation, designer.sfm.rolling_adjustment)."""
    if errors is None:
        rec.update_point_3d_errors()
        bad = [pid for pid, pt in rec.points3D.items() if pt.error > max_px]
    else:
        bad = [pid for pid in rec.points3D if pid in errors and np.mean(errors[pid]) > max_px]
    for pid in bad:
        rec.delete_point3D(pid)
    return len(bad)


def mean_reprojection_error_px(rec, errors: dict | None) -> float:
    """The mean reprojection error of the tie points kept (px; as COLMAP defines it, the
    mean over points of each point's mean error): COLMAP's, or with rolling-shutter
    compensation the compensated one."""
    if errors is None:
        rec.update_point_3d_errors()
        return float(rec.compute_mean_reprojection_error())
    kept = [np.mean(errors[pid]) for pid in rec.points3D if pid in errors]
    return float(np.mean(kept)) if kept else 0.0
