"""Compare a point cloud with the true mesh and write the accuracy products.

:func:`compare_cloud` is what ``designer compare`` and ``designer reconstruct`` call:
data in, files out —

* ``distances.ply``: the cloud with its signed distance (see :mod:`.writers`);
* ``summary.json``: inputs, statistics, error-map geometry, GCP and camera errors;
* ``histogram.png``, ``error_map.png``, ``error_map.tif`` (GeoTIFF) and
  ``error_map.npy``;
* ``report.md`` and ``report.html``.

:func:`reference_mesh` loads the mesh from a file (PLY/OBJ/STL) or builds it from a
project XML (its terrain and scene objects, plus the GCP target plates when
``with_targets``); :func:`reference_meshes` gives several surfaces (DTM and DSM) of one
project from one build of its terrain.
"""

from __future__ import annotations

import json
import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.core.bounds import column_bounds
from designer.errors import DesignerError
from designer.evaluate.point_clouds import MAX_COORDINATE_SPACING_M, PointCloud
from designer.evaluate.statistics import DEFAULT_TOLERANCES_M, distance_statistics


@dataclass(frozen=True, eq=False)
class ReferenceMesh:
    """World-coordinate triangles: ``vertices`` (N, 3) float64, ``faces`` (M, 3)."""

    vertices: np.ndarray
    faces: np.ndarray
    source: str
    crs: str | None = None
    #: "dtm" or "dsm" when built from a project, ``None`` for a mesh file
    surface: str | None = None
    #: (x_min, x_max, y_min, y_max) world m of the project's area of interest (its
    #: declared terrain extent), None for a mesh file
    area_of_interest_m: tuple[float, float, float, float] | None = None


def reference_mesh(path: str | os.PathLike, *, with_targets: bool = True,
                   at_time_s: float | None = None, surface: str = "dsm",
                   growth=None) -> ReferenceMesh:
    """The true surface from a mesh file or a project XML: its bare earth (``surface``
    "dtm": terrain and GCP targets) or the surface with what stands on it ("dsm": plus
    scene objects, buildings, vegetation; moving objects only with ``at_time_s``, posed
    then, seconds after take-off). See :mod:`designer.scene.surfaces`; ``growth`` grows a
    project's terrain by its surroundings as the renderer did
    (:func:`designer.survey.surroundings.project_surroundings`)."""
    return reference_meshes(path, surfaces=(surface,), with_targets=with_targets,
                            at_time_s=at_time_s, growth=growth)[surface]


def reference_meshes(path: str | os.PathLike, *, surfaces=("dtm", "dsm"),
                     with_targets: bool = True,
                     at_time_s: float | None = None, growth=None) -> dict[str, ReferenceMesh]:
    """:func:`reference_mesh` for each of ``surfaces``, keyed by name, from one load of
    the project and one build of its terrain. A mesh file is its own surface: the one
    mesh stands under every name."""
    path = Path(path)
    surfaces = (surfaces,) if isinstance(surfaces, str) else tuple(surfaces)
    if path.suffix.lower() == ".xml":
        from designer.project import load_project
        from designer.scene.surfaces import true_surfaces

        project = load_project(path)
        built = true_surfaces(project, path.parent, surfaces, with_targets=with_targets,
                              at_time_s=at_time_s, growth=growth)
        e = project.scene.terrain.extent
        aoi = (e.min_X, e.max_X, e.min_Y, e.max_Y)
        return {surface: ReferenceMesh(vertices, faces, str(path), project.crs, surface, aoi)
                for surface, (vertices, faces) in built.items()}
    from designer.scene.mesh import load_mesh

    mesh = load_mesh(path)
    reference = ReferenceMesh(mesh.vertices_world, mesh.faces, str(path))
    return dict.fromkeys(surfaces, reference)


#: the areas ``designer compare`` takes its statistics over
AREAS = ("aoi", "all")


def crop_to_area(cloud: PointCloud, mesh: ReferenceMesh, area: str = "aoi"
                 ) -> tuple[PointCloud, dict]:
    """The points of ``cloud`` the statistics cover, and a record of that area: "aoi"
    keeps the points over the project's area of interest (its declared terrain extent),
    "all" every point (as does a mesh file, which has no area of interest)."""
    if area not in AREAS:
        raise DesignerError(f"area {area!r}: give one of {', '.join(AREAS)}")
    box = mesh.area_of_interest_m
    if area == "all" or box is None:
        return cloud, {"name": "all points", "extent_m": None, "points_left_out": 0}
    x0, x1, y0, y1 = box
    xy = cloud.xyz[:, :2]
    inside = (xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)
    kept = PointCloud(cloud.xyz[inside], None if cloud.rgb is None else cloud.rgb[inside],
                      None if cloud.normals is None else cloud.normals[inside], cloud.source,
                      cloud.coordinate_spacing_m)
    return kept, {"name": "area of interest (the declared terrain extent)",
                  "extent_m": [float(v) for v in box],
                  "points_left_out": int(np.count_nonzero(~inside))}


def check_overlap(cloud_xyz: np.ndarray, vertices: np.ndarray, cloud_name: str,
                  mesh_name: str) -> None:
    """Raise a one-line error when cloud and mesh are obviously in different coordinates."""
    c_lo, c_hi = column_bounds(cloud_xyz)
    m_lo, m_hi = column_bounds(vertices)
    gap = np.maximum(0.0, np.maximum(c_lo - m_hi, m_lo - c_hi))
    size = max(float(np.max(m_hi - m_lo)), 1.0)
    if np.linalg.norm(gap) > 10 * size:
        cc, mc = 0.5 * (c_lo + c_hi), 0.5 * (m_lo + m_hi)
        raise DesignerError(
            f"{cloud_name} (centre {cc[0]:.1f}, {cc[1]:.1f}, {cc[2]:.1f}) lies far from "
            f"{mesh_name} (centre {mc[0]:.1f}, {mc[1]:.1f}, {mc[2]:.1f}): are they in the same "
            "coordinates? Give the cloud's offset with --offset E N H")


def coarse_warnings(cloud: PointCloud) -> list[str]:
    """A warning when the cloud's stored coordinates are coarser than the comparison
    resolves (it was read knowingly with ``allow_coarse``); [] otherwise."""
    spacing = cloud.coordinate_spacing_m
    if spacing is None or spacing <= MAX_COORDINATE_SPACING_M:
        return []
    return [f"the cloud's stored coordinates are spaced {spacing * 1000:.4g} mm apart "
            f"(> {MAX_COORDINATE_SPACING_M * 1000:g} mm): the distances include that "
            "quantisation"]


def compare_cloud(
    cloud: PointCloud,
    mesh: ReferenceMesh,
    out_dir: str | os.PathLike,
    *,
    max_distance: float | None = None,
    tolerances=DEFAULT_TOLERANCES_M,
    cell_m: float | None = None,
    gcps: dict | None = None,
    cameras: dict | None = None,
    offset=None,
    area: dict | None = None,
) -> dict:
    """Signed distances of ``cloud`` to ``mesh``, statistics and every product in
    ``out_dir`` (created); returns the summary written to summary.json. ``area`` is the
    record of the area ``cloud`` was cropped to (:func:`crop_to_area`), for the report.

    ``gcps`` / ``cameras`` are results of :func:`~designer.evaluate.gcp.gcp_errors` and
    :func:`~designer.evaluate.poses.camera_pose_errors` to include in the report.
    """
    from designer.evaluate.distance import build_mesh_index, signed_distances
    from designer.evaluate.figures import take_figure_writer
    from designer.evaluate.maps import (
        grid_errors,
        write_error_map_geotiff,
        write_error_map_npy,
    )
    from designer.evaluate.report import write_report
    from designer.evaluate.writers import write_distances_ply

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    check_overlap(cloud.xyz, mesh.vertices, cloud.source or "the cloud", mesh.source)
    files = {"distances": "distances.ply", "histogram": "histogram.png",
             "error_map": "error_map.png", "error_map_geotiff": "error_map.tif",
             "error_map_npy": "error_map.npy"}
    # the figures are drawn by the writer started before the distances, so its imports
    # overlap them (a thread, or two processes for `designer compare`), while this
    # thread writes the other products
    with take_figure_writer() as figures:
        t0 = time.perf_counter()
        index = build_mesh_index((mesh.vertices, mesh.faces))
        t1 = time.perf_counter()
        d = signed_distances(cloud.xyz, index, max_distance=max_distance)
        t2 = time.perf_counter()
        if not np.isfinite(d).any():  # before any file is written
            distance_statistics(d, tolerances)  # raises its one-line error
        # the largest file, and the error map's grid, in threads of their own (copying,
        # file output and the grid's kernel release the GIL) while the statistics are
        # computed
        with ThreadPoolExecutor(max_workers=2, thread_name_prefix="designer-products") as pool:
            ply = pool.submit(write_distances_ply, out / files["distances"], cloud.xyz, d,
                              rgb=cloud.rgb, normals=cloud.normals,
                              comments=(f"reference mesh {Path(mesh.source).name}",))
            gridding = pool.submit(grid_errors, cloud.xyz[:, :2], d, cell_m=cell_m)
            try:
                stats = distance_statistics(d, tolerances)
                figures.submit("write_histogram_png", out / files["histogram"], stats)
                grid = gridding.result()
                figures.submit("write_error_map_png", out / files["error_map"], grid,
                               limit_m=stats["abs_q95"] or None)
                # here, not in the figure thread: both threads finish together
                write_error_map_geotiff(out / files["error_map_geotiff"], grid, mesh.crs)
                write_error_map_npy(out / files["error_map_npy"], grid)
            except BaseException:
                if ply.exception() is None:  # (waits for it) no results of a failed run
                    (out / files["distances"]).unlink(missing_ok=True)
                raise
        ply.result()  # re-raises the writer's error
    rows, cols = grid.values.shape
    summary = {
        "inputs": {"cloud": cloud.source, "n_points": len(cloud), "mesh": mesh.source,
                   "surface": mesh.surface, "n_faces": len(mesh.faces), "crs": mesh.crs,
                   "offset": None if offset is None else [float(v) for v in offset],
                   "max_distance": max_distance,
                   "coordinate_spacing_m": cloud.coordinate_spacing_m},
        "warnings": coarse_warnings(cloud),
        "area": area or {"name": "all points", "extent_m": None, "points_left_out": 0},
        "convention": "signed distance = point to nearest mesh point (m), positive on the "
                      "side the mesh normals face (above the terrain)",
        "timing": {"index_s": t1 - t0, "distances_s": t2 - t1},
        "distances": stats,
        "error_map": {"cell_m": grid.cell_m, "x_min": grid.x_min, "y_max": grid.y_max,
                      "rows": rows, "cols": cols,
                      "filled_share": float(np.isfinite(grid.values).mean())},
        "gcps": gcps, "cameras": cameras, "files": files,
    }
    report = write_report(out, summary, {"histogram": files["histogram"],
                                         "error_map": files["error_map"]})
    summary["files"].update({"report_markdown": report["markdown"].name,
                             "report_html": report["html"].name,
                             "summary": "summary.json"})
    write_text_atomic(out / "summary.json", json.dumps(summary, indent=1) + "\n")
    return summary
