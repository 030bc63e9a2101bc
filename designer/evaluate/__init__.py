"""Accuracy assessment: point clouds against the true mesh, GCP and camera pose errors.

Layer: evaluation (numpy, scipy, numba; matplotlib and rasterio lazily). Nothing here
imports Blender or Qt. The public functions take data, not paths, except the readers
and writers:

* :func:`signed_distances` / :func:`build_mesh_index` — exact signed point-to-mesh
  distances (:mod:`.distance`);
* :func:`distance_statistics` — n, mean, std, RMSE, median, NMAD, |d| quantiles,
  tolerance shares, histogram (:mod:`.statistics`);
* :func:`read_point_cloud` — PLY, LAS/LAZ, XYZ/CSV/TXT, COLMAP points3D (:mod:`.clouds`);
* :func:`grid_errors`, :func:`write_error_map_png` and friends (:mod:`.maps`);
* :func:`write_distances_ply` (:mod:`.writers`);
* :func:`gcp_errors`, :func:`triangulate_gcps` (:mod:`.gcp`, :mod:`.triangulate`);
* :func:`camera_pose_errors`, :func:`similarity_transform`, :func:`read_camera_poses`
  (:mod:`.poses`);
* :func:`compare_cloud`, :func:`reference_mesh`, :func:`write_report`
  (:mod:`.compare`, :mod:`.report`).
"""

from designer.evaluate.clouds import PointCloud, read_point_cloud
from designer.evaluate.compare import ReferenceMesh, compare_cloud, reference_mesh
from designer.evaluate.distance import MeshIndex, build_mesh_index, signed_distances
from designer.evaluate.gcp import gcp_errors, read_gcp_estimates_csv
from designer.evaluate.maps import (
    ErrorGrid,
    grid_errors,
    write_error_map_geotiff,
    write_error_map_npy,
    write_error_map_png,
    write_histogram_png,
)
from designer.evaluate.poses import camera_pose_errors, read_camera_poses, similarity_transform
from designer.evaluate.report import format_summary, write_report
from designer.evaluate.statistics import DEFAULT_TOLERANCES_M, distance_statistics
from designer.evaluate.triangulate import triangulate_gcps
from designer.evaluate.writers import write_distances_ply

__all__ = [
    "DEFAULT_TOLERANCES_M", "ErrorGrid", "MeshIndex", "PointCloud", "ReferenceMesh",
    "build_mesh_index", "camera_pose_errors", "compare_cloud", "distance_statistics",
    "format_summary", "gcp_errors", "grid_errors", "read_camera_poses", "read_gcp_estimates_csv",
    "read_point_cloud", "reference_mesh", "signed_distances", "similarity_transform",
    "triangulate_gcps", "write_distances_ply", "write_error_map_geotiff", "write_error_map_npy",
    "write_error_map_png", "write_histogram_png", "write_report",
]
