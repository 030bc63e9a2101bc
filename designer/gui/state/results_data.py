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
    path: Path | None = None

    def rows(self) -> list[tuple[str, str]]:
        return robust_rows(self.distances_m)

    def outliers(self) -> np.ndarray:
        """Indices of the outliers, the largest |Δ| first (at most LISTED_OUTLIERS)."""
        idx = np.flatnonzero(outlier_mask(self.distances_m))
        order = np.argsort(-np.abs(np.nan_to_num(self.distances_m[idx], nan=np.inf)))
        return idx[order][:LISTED_OUTLIERS]

    @property
    def n_outliers(self) -> int:
        return int(outlier_mask(self.distances_m).sum())


#: a point is an outlier when |Δ − median| exceeds this many NMAD …
OUTLIER_NMAD_MULTIPLE = 5.0
#: … and this distance (m): a near-perfect cloud has no outliers at the 0.1 mm level
OUTLIER_MIN_M = 0.005
#: the colour range's step and least value (m): 0.1 mm, as its field in the Results panel
#: shows it (a range the field cannot show would be applied without being seen)
COLOUR_RANGE_STEP_M = 1e-4
#: bins of the histogram over the colour range
HISTOGRAM_BINS = 60
#: outliers listed by the panel (the largest |Δ| first)
LISTED_OUTLIERS = 50


def robust_centre_scale(d: np.ndarray) -> tuple[float, float]:
    """Median and NMAD (1.4826 × median absolute deviation) of the finite values (m)."""
    f = np.asarray(d, dtype=float)
    f = f[np.isfinite(f)]
    if not f.size:
        return 0.0, 0.0
    median = float(np.median(f))
    return median, 1.4826 * float(np.median(np.abs(f - median)))


def outlier_threshold_m(d: np.ndarray) -> float:
    """Points with |Δ − median| above this (m) are outliers: OUTLIER_NMAD_MULTIPLE ×
    NMAD, but at least OUTLIER_MIN_M."""
    _median, nmad = robust_centre_scale(d)
    return max(OUTLIER_NMAD_MULTIPLE * nmad, OUTLIER_MIN_M)


def outlier_mask(d: np.ndarray) -> np.ndarray:
    """(N,) True for the outliers (and for non-finite distances)."""
    d = np.asarray(d, dtype=float)
    median, _nmad = robust_centre_scale(d)
    with np.errstate(invalid="ignore"):
        return ~(np.abs(d - median) <= outlier_threshold_m(d))


def colour_limit_m(d: np.ndarray) -> float:
    """Symmetric colour range ±L: the 98th percentile of |Δ| of the points that are not
    outliers (a handful of gross errors cannot stretch it), to COLOUR_RANGE_STEP_M and
    at least that."""
    d = np.asarray(d, dtype=float)
    a = np.abs(d[~outlier_mask(d)])
    if not a.size:
        a = np.abs(d[np.isfinite(d)])
    if not a.size:
        return 1.0
    steps = round(float(np.quantile(a, 0.98)) / COLOUR_RANGE_STEP_M)
    return max(steps, 1) * COLOUR_RANGE_STEP_M


def robust_rows(d: np.ndarray) -> list[tuple[str, str]]:
    """(label, value) rows, robust figures first: median, NMAD, quantiles, outliers;
    then the figures every point sways (mean, std, RMSE) with and without outliers."""
    d = np.asarray(d, dtype=float)
    f = d[np.isfinite(d)]
    median, nmad = robust_centre_scale(f)
    out = outlier_mask(f)
    q = np.quantile(f, [0.05, 0.25, 0.75, 0.95])
    absq = np.quantile(np.abs(f), [0.683, 0.95])
    inl = f[~out]
    limit = outlier_threshold_m(f)

    def mm(v: float) -> str:
        return f"{1000 * v:+.1f} mm" if abs(v) < 10 else f"{v:+.3f} m"

    def mag(v: float) -> str:
        return f"{1000 * v:.1f} mm" if abs(v) < 10 else f"{v:.3f} m"

    rows = [("points", f"{f.size:,}"), ("median", mm(median)), ("NMAD", mag(nmad)),
            ("5 % / 95 % quantile", f"{mm(q[0])} / {mm(q[3])}"),
            ("25 % / 75 % quantile", f"{mm(q[1])} / {mm(q[2])}"),
            ("68.3 % / 95 % of |Δ| within", f"{mag(absq[0])} / {mag(absq[1])}"),
            (f"outliers (|Δ − median| > {mag(limit)}: "
             f"{OUTLIER_NMAD_MULTIPLE:g} × NMAD, ≥ {mag(OUTLIER_MIN_M)})",
             f"{int(out.sum()):,} ({100 * out.mean():.2f} %)")]
    if inl.size:
        rows += [("RMSE without outliers", mag(float(np.sqrt(np.mean(inl * inl))))),
                 ("mean / std without outliers",
                  f"{mm(float(inl.mean()))} / {mag(float(inl.std()))}")]
    rows += [("RMSE, all points", mag(float(np.sqrt(np.mean(f * f))))),
             ("mean / std, all points", f"{mm(float(f.mean()))} / {mag(float(f.std()))}"),
             ("min / max", f"{mm(float(f.min()))} / {mm(float(f.max()))}")]
    if f.size != d.size:
        rows.append(("left out (no distance)", f"{d.size - f.size:,}"))
    return rows


def clipped_histogram(d: np.ndarray, limit_m: float, bins: int = HISTOGRAM_BINS
                      ) -> tuple[np.ndarray, np.ndarray, int, int]:
    """Histogram over [−L, L]: (edges, counts, n below −L, n above +L)."""
    f = np.asarray(d, dtype=float)
    f = f[np.isfinite(f)]
    counts, edges = np.histogram(f, bins=bins, range=(-limit_m, limit_m))
    return edges, counts, int(np.sum(f < -limit_m)), int(np.sum(f > limit_m))


def cloud_from_arrays(points_world: np.ndarray, distances_m: np.ndarray, name: str = "cloud",
                      reference: str = "", path: Path | None = None) -> CloudResult:
    """A result from points and their distances (however they were computed)."""
    from designer.evaluate import distance_statistics

    d = np.asarray(distances_m, dtype=float).reshape(-1)
    points = np.asarray(points_world, dtype=float).reshape(-1, 3)
    if len(points) != len(d):
        raise DesignerError(f"{len(points)} points but {len(d)} distances")
    return CloudResult(name, points, d, distance_statistics(d), colour_limit_m(d), reference,
                       path)


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
    what = ("the terrain as edited (unsaved changes: the GCP plates left out)"
            if project_path is not None else "the terrain of the unsaved project")
    return (mesh.vertices_world, mesh.faces), what


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
    from designer.gui.state.reconstruct_job import read_compared_cloud

    xyz, d = read_compared_cloud(Path(path))
    if len(xyz) == 0:
        raise DesignerError(f"{path}: the compared cloud has no points")
    return cloud_from_arrays(xyz, d, Path(path).parent.parent.name + "/cloud.ply", reference,
                             Path(path))


@dataclass(frozen=True)
class FoundReconstruction:
    """A reconstruction of a survey found on disk: ``out_dir``, ``designer reconstruct``'s
    folder (summary.json, gcp_residuals.csv, the dense products), ``distances_ply``, the
    comparison's cloud, and the ``--mode`` it was made with (None: not known)."""

    out_dir: Path
    distances_ply: Path
    mode: str | None


def reconstructions_of(survey_dir: Path) -> list[FoundReconstruction]:
    """Where designer's commands put a reconstruction of ``survey_dir`` and its
    comparison with the truth: the window's and ``designer reconstruct``'s
    SURVEY/reconstruction-MODE (compared into its compare/), and, for a survey folder
    named as ``designer demo`` names it, the reconstruction beside it
    (:data:`designer.core.layout.SIDE_BY_SIDE_RECONSTRUCTION_DIR`, compared into
    :data:`~designer.core.layout.SIDE_BY_SIDE_ACCURACY_DIR`, made with --mode free).
    Only those whose comparison exists."""
    from designer.core import layout
    from designer.gui.state.reconstruct_job import MODES, ReconstructJob

    survey_dir = Path(survey_dir)
    found = []
    for _text, mode in MODES:
        job = ReconstructJob(Path(), survey_dir, mode)
        found.append(FoundReconstruction(job.out_dir, job.distances_ply, mode))
    if survey_dir.name == layout.SIDE_BY_SIDE_SURVEY_DIR:
        beside = survey_dir.parent
        found.append(FoundReconstruction(
            beside / layout.SIDE_BY_SIDE_RECONSTRUCTION_DIR,
            beside / layout.SIDE_BY_SIDE_ACCURACY_DIR / "distances.ply", "free"))
    return [f for f in found if f.distances_ply.is_file()]


def last_reconstruction(survey_dir: Path) -> FoundReconstruction | None:
    """The newest reconstruction of ``survey_dir`` (:func:`reconstructions_of`) by its
    comparison's time, or None."""
    found = reconstructions_of(survey_dir)
    return max(found, key=lambda f: f.distances_ply.stat().st_mtime) if found else None


def draw_histogram(figure, d: np.ndarray, limit_m: float, cmap_name: str) -> tuple[int, int]:
    """Draw the histogram of ``d`` (m) over ±limit_m into a matplotlib figure, in mm,
    bars coloured as the cloud; returns the counts below and above the range."""
    import matplotlib

    edges, counts, below, above = clipped_histogram(d, limit_m)
    edges = 1000 * edges
    lim = 1000 * limit_m
    figure.clear()
    ax = figure.add_subplot()
    centres = (edges[:-1] + edges[1:]) / 2
    cmap = matplotlib.colormaps[cmap_name]
    ax.bar(centres, counts, width=np.diff(edges),
           color=[cmap(0.5 + 0.5 * np.clip(c / lim, -1, 1)) for c in centres])
    ax.axvline(0, color="k", lw=0.8)
    ax.set_xlim(-lim, lim)
    ax.set_xlabel("signed distance (mm)")
    ax.set_ylabel("points")
    return below, above


def residual_lines(rows: list[dict], extent: m.Extent
                   ) -> tuple[np.ndarray, np.ndarray, list[str], float]:
    """GCP errors (``gcp_errors`` rows) as lines from each true position to the estimate
    exaggerated by a power of ten, so the largest is about 3 % of the terrain's size:
    (start (N, 3), end (N, 3), labels, factor)."""
    est = np.array([[g["X"], g["Y"], g["Z"]] for g in rows])
    d = np.array([[g["dX"], g["dY"], g["dZ"]] for g in rows])
    biggest = float(np.max(np.linalg.norm(d, axis=1)))
    scale = 1.0
    if biggest > 0:
        scale = max(1.0, 10.0 ** round(np.log10(
            0.03 * max(extent.width_m, extent.length_m) / biggest)))
    true = est - d
    labels = [f"{g['gcp_id']} {1000 * g['dXYZ']:.0f} mm" for g in rows]
    return true, true + scale * d, labels, scale
