"""Results of a reconstruction, ready to show (Qt-free): a point cloud with its signed
distances to the true surface, their statistics and histogram, and GCP errors.

Everything is computed by :mod:`designer.evaluate` (readers, exact signed point-to-mesh
distances — positive above the surface — statistics, GCP errors); this module only
gathers the inputs from the open project and shapes the answers for the panel.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError
from designer.project import model as m


@dataclass(frozen=True, eq=False)
class CloudResult:
    """A cloud (world, m), its signed distances (m) and ``designer.evaluate`` statistics
    (``distance_statistics``' dict); ``limit_m`` is the symmetric colour range."""

    name: str
    points_world: np.ndarray
    distances_m: np.ndarray
    stats: dict
    limit_m: float
    reference: str = ""

    def rows(self) -> list[tuple[str, str]]:
        from designer.evaluate.statistics import format_statistics

        return format_statistics(self.stats)


def colour_limit_m(d: np.ndarray) -> float:
    """Symmetric colour range ±L: the 98th percentile of |Δ| (outliers saturate)."""
    a = np.abs(np.asarray(d, dtype=float))
    a = a[np.isfinite(a)]
    return float(max(np.quantile(a, 0.98), 1e-6)) if a.size else 1.0


def cloud_from_arrays(points_world: np.ndarray, distances_m: np.ndarray, name: str = "cloud",
                      reference: str = "") -> CloudResult:
    """A result from points and their distances (however they were computed)."""
    from designer.evaluate import distance_statistics

    d = np.asarray(distances_m, dtype=float).reshape(-1)
    points = np.asarray(points_world, dtype=float).reshape(-1, 3)
    if len(points) != len(d):
        raise DesignerError(f"{len(points)} points but {len(d)} distances")
    return CloudResult(name, points, d, distance_statistics(d), colour_limit_m(d), reference)


def truth_mesh(project_path: Path | None, dirty: bool, heightfield=None, mesh=None):
    """The true surface: ``designer.evaluate.reference_mesh`` of the saved project
    (terrain and GCP plates), or the open terrain alone while the project is unsaved.
    Returns ((vertices, faces), description)."""
    if project_path is not None and not dirty:
        from designer.evaluate import reference_mesh

        ref = reference_mesh(project_path)
        return (ref.vertices, ref.faces), f"terrain and targets of {project_path.name}"
    if heightfield is not None:
        from designer.scene.mesh import heightfield_to_mesh

        mesh = heightfield_to_mesh(heightfield)
    if mesh is None:
        raise DesignerError("no terrain to compare the cloud with")
    return (mesh.vertices_world, mesh.faces), "the terrain of the unsaved project"


def evaluate_cloud(path: Path, project_path: Path | None, dirty: bool, heightfield=None,
                   mesh=None) -> CloudResult:
    """Read a cloud and compute its signed distances to the true surface."""
    from designer.evaluate import read_point_cloud, signed_distances

    cloud = read_point_cloud(path)
    if len(cloud.xyz) == 0:
        raise DesignerError(f"{path}: the cloud has no points")
    surface, description = truth_mesh(project_path, dirty, heightfield, mesh)
    d = signed_distances(cloud.xyz, surface)
    return cloud_from_arrays(cloud.xyz, d, Path(path).name, description)


def gcp_truth(project: m.Project, heightfield) -> list:
    """The project's GCPs as ``GroundControlPoint`` (true and surveyed coordinates)."""
    from designer.core.truth import GroundControlPoint
    from designer.scene.build import build_targets

    return [GroundControlPoint(b.target.id, b.target.role, b.true_xyz, b.surveyed_xyz,
                               b.sigma_xyz) for b in build_targets(project, heightfield)]


def evaluate_gcps(path: Path, project: m.Project, heightfield) -> dict:
    """``designer.evaluate.gcp_errors`` of the estimates in a CSV (``gcp_residuals.csv`` of
    ``designer reconstruct``, or any id, X, Y, Z table) against the project's truth."""
    from designer.evaluate import gcp_errors, read_gcp_estimates_csv

    return gcp_errors(read_gcp_estimates_csv(path), gcp_truth(project, heightfield))


def load_compared_cloud(path: Path, reference: str = "") -> CloudResult:
    """The cloud and distances ``designer compare`` wrote (``distances.ply``)."""
    from designer.gui.reconstruct_job import read_compared_cloud

    xyz, d = read_compared_cloud(Path(path))
    if len(xyz) == 0:
        raise DesignerError(f"{path}: the compared cloud has no points")
    return cloud_from_arrays(xyz, d, Path(path).parent.parent.name + "/cloud.ply", reference)
