"""Accuracy assessment: point clouds against the true mesh, GCP and camera pose errors.

Layer: evaluation (numpy, scipy, compiled C kernels; matplotlib and rasterio lazily).
Nothing here imports Blender or Qt. The public functions take data, not paths, except
the readers and writers:

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

from typing import TYPE_CHECKING

from designer._lazy import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    "DEFAULT_TOLERANCES_M": "designer.evaluate.statistics",
    "ErrorGrid": "designer.evaluate.maps",
    "MeshIndex": "designer.evaluate.distance",
    "PointCloud": "designer.evaluate.point_clouds",
    "ReferenceMesh": "designer.evaluate.compare",
    "build_mesh_index": "designer.evaluate.distance",
    "camera_pose_errors": "designer.evaluate.poses",
    "compare_cloud": "designer.evaluate.compare",
    "distance_statistics": "designer.evaluate.statistics",
    "format_summary": "designer.evaluate.report",
    "gcp_errors": "designer.evaluate.gcp",
    "grid_errors": "designer.evaluate.maps",
    "read_camera_poses": "designer.evaluate.poses",
    "read_gcp_estimates_csv": "designer.evaluate.gcp",
    "read_point_cloud": "designer.evaluate.point_clouds",
    "reference_mesh": "designer.evaluate.compare",
    "signed_distances": "designer.evaluate.distance",
    "similarity_transform": "designer.evaluate.poses",
    "triangulate_gcps": "designer.evaluate.triangulate",
    "write_distances_ply": "designer.evaluate.writers",
    "write_error_map_geotiff": "designer.evaluate.maps",
    "write_error_map_npy": "designer.evaluate.maps",
    "write_error_map_png": "designer.evaluate.maps",
    "write_histogram_png": "designer.evaluate.maps",
    "write_report": "designer.evaluate.report",
})

if TYPE_CHECKING:
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
    from designer.evaluate.point_clouds import PointCloud, read_point_cloud
    from designer.evaluate.poses import camera_pose_errors, read_camera_poses, similarity_transform
    from designer.evaluate.report import format_summary, write_report
    from designer.evaluate.statistics import DEFAULT_TOLERANCES_M, distance_statistics
    from designer.evaluate.triangulate import triangulate_gcps
    from designer.evaluate.writers import write_distances_ply
