"""How often the incremental mapper adjusts the whole model (``designer bench mapper
--survey DIR``): COLMAP's incremental mapper on one rendered survey, once per growth
ratio of its global bundle adjustments, everything else as ``designer reconstruct
--mode free`` sets it.

COLMAP adjusts the whole model each time the registered images (or the tie points) have
grown by a ratio since the last such adjustment (``ba_global_frames_ratio`` and
``ba_global_points_ratio``, 1.1 by default, which designer's mapper keeps). This bench
measures what a larger ratio saves on a survey-size block and whether the cameras move:
per ratio, the mapper's wall and CPU seconds (all of its threads), the images
registered, and the camera centres' RMS against the truth in XY and Z (m) after a
similarity (Umeyama) of the free network onto the true centres.

Features and matches are the project's own (designer.sfm.features), kept in
``DIR/../feature-cache``: a block of ``designer bench scale`` (``bench-scale/block-N/
survey``) already holds them, so only the mapper runs. Each ratio maps its own copy of
the matched database; all of it in a temporary folder removed at the end, nothing
written next to the survey but the cache.
"""

from __future__ import annotations

import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

RATIOS = (1.1, 1.4)


def run(repeats: int = 1, scale: float = 1.0, survey: Path | None = None,
        on_row=None) -> list[dict]:
    """One row per global-adjustment growth ratio (:data:`RATIOS`) on ``survey``."""
    from designer.errors import DesignerError

    if survey is None:
        raise DesignerError("designer bench mapper: give --survey DIR, a rendered survey "
                            "(e.g. bench-scale/block-720/survey from 'designer bench scale')")
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench-mapper-") as tmp:
        db, inputs = _matched_database(Path(survey), Path(tmp))
        for ratio in RATIOS:
            row = _map_once(db, inputs, ratio)
            rows.append(row)
            if on_row is not None:
                on_row(row)
    return rows


def _matched_database(survey: Path, work: Path):
    """The survey's features and matches (from the cache beside it, or computed into it)
    in a database in ``work``, and the survey's processing inputs."""
    from designer.sfm.feature_cache import FeatureCache
    from designer.sfm.features import extract_features, match_features
    from designer.sfm.inputs import read_inputs
    from designer.sfm.settings import resolve_processing

    def log(message: str) -> None:
        print(f"  {message}", flush=True)

    processing = resolve_processing(survey)
    inputs = read_inputs(survey, "free", processing, None, log)
    cache = FeatureCache(survey.parent / "feature-cache")
    features = extract_features(inputs, work / "database.db", cache, log)
    match_features(inputs, features, work, cache, log)
    return features.db_path, inputs


def _map_once(db: Path, inputs, ratio: float) -> dict:
    """The mapper on a copy of ``db`` with global adjustments at growth ``ratio``."""
    import pycolmap

    from designer.sfm.mapping import incremental_sfm

    with tempfile.TemporaryDirectory(prefix="bench-mapper-") as tmp:
        copy, sparse = Path(tmp) / "database.db", Path(tmp) / "sparse"
        shutil.copy(db, copy)
        sparse.mkdir()
        wall0, cpu0 = time.perf_counter(), time.process_time()
        rec = incremental_sfm(pycolmap, copy, inputs.image_dir, sparse,
                              inputs.processing.calibration.mode, global_ba_ratio=ratio)
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    est, true = [], []
    for image in rec.images.values():
        if image.has_pose:
            est.append(image.projection_center())
            true.append(inputs.truth.find_image_with_name(image.name).projection_center())
    rms_xy, rms_z = centre_rms(np.array(est), np.array(true))
    return {"ratio": ratio, "wall_s": wall, "cpu_s": cpu,
            "registered": rec.num_reg_images(), "images": len(inputs.names),
            "centre_rms_xy_m": rms_xy, "centre_rms_z_m": rms_z}


def centre_rms(est: np.ndarray, true: np.ndarray) -> tuple[float, float]:
    """RMS (XY, Z) of ``true`` minus the similarity (Umeyama, with scale) of ``est`` that
    fits it best in least squares (designer.bench.doming.similarity_onto); N × 3 arrays
    of the same cameras."""
    from designer.bench.doming import similarity_onto

    res = true - similarity_onto(est, true)
    return float(np.sqrt((res[:, :2] ** 2).sum(1).mean())), float(np.sqrt((res[:, 2] ** 2).mean()))


def format_table(rows: list[dict]) -> str:
    lines = ["designer bench mapper: COLMAP's incremental mapper, global adjustments at "
             "each growth ratio",
             f"{'ratio':>6} {'wall s':>8} {'CPU s':>8} {'registered':>11} "
             f"{'centre RMS XY cm':>17} {'Z cm':>7}"]
    for r in rows:
        lines.append(f"{r['ratio']:6.2f} {r['wall_s']:8.1f} {r['cpu_s']:8.1f} "
                     f"{r['registered']:>5}/{r['images']:<5} "
                     f"{r['centre_rms_xy_m'] * 100:17.2f} {r['centre_rms_z_m'] * 100:7.2f}")
    lines.append("ratio: the model's growth (images and tie points) between two global "
                 "adjustments (COLMAP's default and designer's: 1.1); CPU: all threads; "
                 "centre RMS after a similarity onto the true centres")
    return "\n".join(lines)
