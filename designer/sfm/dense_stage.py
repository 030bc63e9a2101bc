"""The dense stage of ``designer reconstruct``: dense cloud, LAZ, DSM and DEM of difference.

Runs after the sparse reconstruction on its model (shifted into the local frame the
reconstruction used), with the CPU matcher of :mod:`designer.sfm.dense`; the raster
products compare the dense cloud with the project's true surface
(:mod:`designer.evaluate.raster_products`). Writes into the reconstruction folder::

    dense.ply  dense.laz  dsm.tif  surface.tif  dod.tif  dod.png  dod_profile.png
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from designer.core.layout import images_dir
from designer.errors import DesignerError

#: DSM cell size as a multiple of the survey's GSD (a cell holds ~16 image pixels' points)
DSM_CELL_GSD = 4.0
#: the matcher ``--dense auto`` picks on a machine without CUDA (none here has a GPU)
AUTO_MATCHER = "cpu"


def epsg_of(crs: str) -> int | None:
    """The EPSG code of a project CRS label ('EPSG:32632 (…)' → 32632), or None."""
    from designer.core.crs import crs_token

    token = crs_token(crs)
    if token.upper().startswith("EPSG:") and token[5:].isdigit():
        return int(token[5:])
    return None


def run_dense_stage(survey: Path, out: Path, model_dir: Path, project_path: Path | None,
                    offset_world: np.ndarray, gsd_m: float, *,
                    max_image_size_px: int | None = None,
                    log: Callable[[str], None] = print) -> dict:
    """Dense cloud of the images of the render output ``survey`` from the world-frame
    COLMAP model in ``model_dir``; products into ``out``. Returns the ``dense`` section of
    summary.json (points, matcher, seconds per stage, DoD statistics and dome amplitude)."""
    from designer.sfm.dense import dense_cloud, write_dense_ply, write_las, write_local_model

    if project_path is None:
        raise DesignerError(f"{survey}: dense products need the project (its true surface and "
                            "CRS); give --project or render the survey with designer render")
    from designer.evaluate.compare import reference_mesh
    from designer.evaluate.raster_products import write_raster_products
    from designer.project import load_project
    from designer.sfm.dome import survey_area_world

    project = load_project(project_path)
    truth = reference_mesh(project_path)
    seconds: dict[str, float] = {}
    t = time.perf_counter()
    local_model = out / "dense-model"
    origin = write_local_model(model_dir, local_model, origin_world=offset_world)
    lo = truth.vertices.min(axis=0) - [0.0, 0.0, 5.0]
    hi = truth.vertices.max(axis=0) + [0.0, 0.0, 5.0]
    log(f"dense matching ({'full size' if not max_image_size_px else max_image_size_px} px)")
    cloud = dense_cloud(images_dir(survey), local_model, out / "dense-work", origin_world=origin,
                        max_image_size_px=max_image_size_px, log=log, bounds_world=(lo, hi))
    seconds["dense_s"] = time.perf_counter() - t
    write_dense_ply(out / "dense.ply", cloud)
    write_las(out / "dense.laz", cloud, epsg_of(project.crs), origin)
    t = time.perf_counter()
    cell_m = DSM_CELL_GSD * gsd_m
    rasters = write_raster_products(out, cloud.points_world, truth, project.crs, cell_m, gsd_m,
                                    survey_area_world=survey_area_world(project))
    seconds["rasters_s"] = time.perf_counter() - t
    return {"status": "ok", "matcher": cloud.matcher, "points": len(cloud),
            "max_image_size_px": max_image_size_px, "dsm_cell_m": cell_m,
            "stage_seconds": {**cloud.stage_seconds, **seconds},
            "dome_amplitude_m": rasters["dome"]["amplitude_m"],
            "dome_amplitude_gsd": rasters["dome"]["amplitude_gsd"],
            "dome_kind": rasters["dome"]["kind"],
            "dome_area": rasters["dome"]["area"],
            "dome_whole_dod_m": rasters["dome_whole_dod"]["amplitude_m"],
            "dome_whole_dod_gsd": rasters["dome_whole_dod"]["amplitude_gsd"],
            "rasters": rasters, **seconds}


def with_dense_stage(summary: dict, survey: Path, out: Path, model_dir: Path,
                     project_path: Path | None, offset_world: np.ndarray, gsd_m: float, *,
                     max_image_size_px: int | None = None,
                     log: Callable[[str], None] = print) -> dict:
    """``summary`` (of summary.json) with the dense stage run (:func:`run_dense_stage`):
    its ``dense`` section filled in (the mode kept) and the dense and raster seconds
    added to its timings."""
    dense = run_dense_stage(survey, out, model_dir, project_path, offset_world, gsd_m,
                            max_image_size_px=max_image_size_px, log=log)
    timings = {**summary["timings"], "dense_s": dense["dense_s"],
               "rasters_s": dense["rasters_s"]}
    return {**summary, "dense": {"mode": summary["dense"]["mode"], **dense},
            "timings": timings, "stage_seconds": timings}
