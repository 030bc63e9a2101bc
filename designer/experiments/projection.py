"""Projection validation: do rendered checkerboard corners sit where the camera model says?

Section 6.1 of the original study, in code. Images are rendered from random poses inside
the checkerboard cube (:mod:`designer.experiments.cube`) with cameras drawn from five
interior orientations (:data:`IO_SETS`: focal length, sensor size, principal point
offset). In every image the Harris detector with sub-pixel refinement
(:mod:`designer.experiments.corners`) finds the corners, which are matched to the corners
projected by ``designer.core.projection``. The differences in x, y and radius must have
a mean of 0, no correlation with the position in the image, the radius or the camera,
and a spread no larger than the detector's own on exactly area-sampled synthetic images
of the same corners (:mod:`designer.experiments.baseline`).

``render_pp_error_px`` renders with the principal point moved by that many pixels from
the one projected — a deliberate camera-mapping bug that the validation must catch.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.errors import DesignerError
from designer.experiments.baseline import BaselineResult, detector_baseline, local_affine
from designer.experiments.corners import Detector
from designer.experiments.cube import (
    CUBE_SIZE_M,
    SQUARES,
    cube_corners,
    cube_walls,
    measurable,
    random_poses,
)
from designer.experiments.jobs import RenderedViews, render_views
from designer.experiments.report import Criterion
from designer.experiments.settings import RenderSettings, quality
from designer.experiments.stats import (
    Correlation,
    ErrorSummary,
    VarianceTest,
    correlations,
    summarise,
    variance_test,
)

#: the 95 % confidence interval of the mean of dx, dy and dr must lie within ± this (px):
#: per camera, and (tighter, as it has more corners) over all cameras together
MAX_MEAN_CI_PX = 0.04
MAX_POOLED_MEAN_CI_PX = 0.015
#: a correlation fails when it is significant (Bonferroni p < ALPHA) and not negligible
ALPHA = 0.01
MIN_RELEVANT_R = 0.1
#: the renderer may add at most this much noise to the detector's (px), if significant
MAX_EXCESS_STD_PX = 0.02
#: at least this fraction of the measurable corners must be found and matched
MIN_FOUND_FRACTION = 0.9
MIN_CORNERS_PER_IMAGE = 20
#: camera parameters take one value per interior orientation: with fewer images than this
#: their correlations (one mean per image) are reported but not judged
MIN_IMAGES_CAMERA_TEST = 20


@dataclass(frozen=True)
class IOSet:
    """An interior orientation for the experiment: its image size is the experiment's."""

    name: str
    focal_length_mm: float
    sensor_width_mm: float
    principal_point_mm: tuple[float, float]

    def interior(self, size_px: tuple[int, int]) -> InteriorOrientation:
        W, H = size_px
        return InteriorOrientation(self.focal_length_mm, self.sensor_width_mm,
                                   self.sensor_width_mm * H / W, W, H, *self.principal_point_mm)


#: five cameras from wide to long, with principal point offsets of 5–17 px at 960 px
IO_SETS = (
    IOSet("1-inch, 8.8 mm", 8.8, 13.2, (0.0, 0.0)),
    IOSet("APS-C, 24 mm", 24.0, 23.5, (0.25, -0.15)),
    IOSet("1/2.3-inch, 2.8 mm", 2.8, 6.17, (-0.04, 0.03)),
    IOSet("full frame, 50 mm", 50.0, 36.0, (0.6, 0.4)),
    IOSet("4/3-inch, 12 mm", 12.0, 17.3, (-0.3, -0.2)),
)


@dataclass(frozen=True)
class ProjectionConfig:
    n_images: int = 25
    size_px: tuple[int, int] = (960, 640)
    settings: RenderSettings = field(default_factory=lambda: quality("metrology"))
    seed: int = 0
    io_sets: tuple[IOSet, ...] = IO_SETS
    n_baseline: int = 1000
    min_square_px: float = 12.0
    margin_px: float = 10.0
    render_pp_error_px: tuple[float, float] = (0.0, 0.0)
    workers: int | None = None


@dataclass
class CornerTable:
    """One row per measurable corner of every image (found or not)."""

    image: np.ndarray  # (N,) image index
    io_set: np.ndarray  # (N,) index into the IO sets
    uv_proj: np.ndarray  # (N, 2) px
    uv_det: np.ndarray  # (N, 2) px, NaN where not found
    found: np.ndarray  # (N,) bool
    pp: np.ndarray  # (N, 2) principal point of the image's camera, px
    jacobian: np.ndarray  # (N, 2, 2) local map of the wall, px per square

    @property
    def d(self) -> np.ndarray:
        return (self.uv_det - self.uv_proj)[self.found]

    @property
    def dr(self) -> np.ndarray:
        f = self.found
        return (np.linalg.norm(self.uv_det[f] - self.pp[f], axis=1)
                - np.linalg.norm(self.uv_proj[f] - self.pp[f], axis=1))

    @property
    def radius(self) -> np.ndarray:
        return np.linalg.norm(self.uv_proj[self.found] - self.pp[self.found], axis=1)


@dataclass
class ProjectionResult:
    config: ProjectionConfig
    corners: CornerTable
    per_io: list[dict[str, ErrorSummary]]  # per IO set: dx, dy, dr
    overall: dict[str, ErrorSummary]
    correlations: list[Correlation]
    baseline: BaselineResult
    variance: VarianceTest
    criteria: list[Criterion]
    views: list[RenderedViews]
    poses: list[list[tuple[np.ndarray, np.ndarray]]]
    render_seconds: float
    wall_seconds: float

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.criteria)


def plan_poses(config: ProjectionConfig) -> list[list[tuple[np.ndarray, np.ndarray]]]:
    """Random poses per IO set (images dealt round-robin), each seeing enough corners."""
    rng = np.random.default_rng(config.seed)
    corners = cube_corners()
    out: list[list] = [[] for _ in config.io_sets]
    for k in range(config.n_images):
        s = k % len(config.io_sets)
        interior = config.io_sets[s].interior(config.size_px)
        for _ in range(1000):
            C, R = random_poses(1, rng)[0]
            ok, _ = measurable(corners, C, R, interior, config.min_square_px, config.margin_px)
            if ok.sum() >= MIN_CORNERS_PER_IMAGE:
                out[s].append((C, R))
                break
        else:
            raise DesignerError(
                f"no random pose of camera '{config.io_sets[s].name}' sees "
                f"{MIN_CORNERS_PER_IMAGE} measurable corners in {config.size_px[0]} x "
                f"{config.size_px[1]} px images; use larger images (--size)")
    return out


def _with_pp_error(interior: InteriorOrientation, error_px: tuple[float, float]
                   ) -> InteriorOrientation:
    du, dv = error_px  # px right and down; the offset in mm is x right, y up
    x0 = interior.principal_point_x_mm + du * interior.pixel_pitch_x_mm
    y0 = interior.principal_point_y_mm - dv * interior.pixel_pitch_y_mm
    return replace(interior, principal_point_x_mm=x0, principal_point_y_mm=y0)


def run_projection(config: ProjectionConfig, work_dir: Path,
                   progress: Callable[[str], None] | None = None) -> ProjectionResult:
    """Render, measure and judge the projection experiment; images go under ``work_dir``."""
    t_start = time.perf_counter()
    say = progress or (lambda _msg: None)
    poses = plan_poses(config)
    corners = cube_corners()
    detector = Detector()
    rows: dict[str, list] = {k: [] for k in ("image", "io", "uv", "det", "found", "pp", "J")}
    views_all, render_seconds, image_index = [], 0.0, 0
    for s, io in enumerate(config.io_sets):
        if not poses[s]:
            continue
        interior = io.interior(config.size_px)
        rendered = _with_pp_error(interior, config.render_pp_error_px)
        say(f"rendering {len(poses[s])} images with camera {s + 1}/{len(config.io_sets)} "
            f"({io.name}), {config.settings.label()}")
        views = render_views(work_dir / f"camera-{s + 1}", [cube_walls()], rendered, poses[s],
                             config.settings, seed=config.seed, workers=config.workers)
        views = replace(views, interior=interior)
        views_all.append(views)
        render_seconds += sum(views.seconds)
        for k, (C, R) in enumerate(poses[s]):
            ok, uv = measurable(corners, C, R, interior, config.min_square_px, config.margin_px)
            found, det = detector.measure(views.gray(k), uv[ok])
            idx = np.nonzero(ok)[0]
            n = len(idx)
            rows["image"].append(np.full(n, image_index))
            rows["io"].append(np.full(n, s))
            rows["uv"].append(uv[ok])
            rows["det"].append(det)
            rows["found"].append(found)
            rows["pp"].append(np.tile([interior.cx_px, interior.cy_px], (n, 1)))
            square = CUBE_SIZE_M / SQUARES
            rows["J"].append(np.array([
                local_affine(corners.xyz_m[i], corners.axis_a[i], corners.axis_b[i], square,
                             C, R, interior) for i in idx]).reshape(-1, 2, 2))
            image_index += 1
    table = CornerTable(*(np.concatenate(rows[k]) for k in
                          ("image", "io", "uv", "det", "found", "pp", "J")))
    say(f"detector baseline: {config.n_baseline} synthetic images")
    rng = np.random.default_rng(config.seed + 1)
    baseline = detector_baseline(table.jacobian[table.found], config.n_baseline, rng, detector)
    result = _analyse(config, table, baseline, poses, views_all, render_seconds)
    result.wall_seconds = time.perf_counter() - t_start
    return result


def _analyse(config, table: CornerTable, baseline: BaselineResult, poses, views,
             render_seconds: float) -> ProjectionResult:
    f = table.found
    d, dr = table.d, table.dr
    io = table.io_set[f]
    errors = {"dx": d[:, 0], "dy": d[:, 1], "dr": dr}
    per_io = [{k: summarise(v[io == s]) for k, v in errors.items()}
              for s in range(len(config.io_sets))]
    overall = {k: summarise(v) for k, v in errors.items()}
    uv, pp = table.uv_proj[f], table.pp[f]
    corner_level = correlations(
        errors, {"x (px from principal point)": uv[:, 0] - pp[:, 0],
                 "y (px from principal point)": uv[:, 1] - pp[:, 1],
                 "radius (px)": table.radius}, "corner")
    # Camera parameters are constant within an image: correlate per-image mean errors,
    # or thousands of corners would pretend to be independent evidence.
    images = np.unique(table.image[f])
    img_of = table.image[f]
    img_io = np.array([io[img_of == i][0] for i in images])
    img_err = {k: np.array([v[img_of == i].mean() for i in images]) for k, v in errors.items()}
    sets = config.io_sets
    camera = {"focal length (mm)": [sets[s].focal_length_mm for s in img_io],
              "sensor width (mm)": [sets[s].sensor_width_mm for s in img_io],
              "principal point x0 (mm)": [sets[s].principal_point_mm[0] for s in img_io],
              "principal point y0 (mm)": [sets[s].principal_point_mm[1] for s in img_io]}
    image_level = correlations({f"mean {k}": v for k, v in img_err.items()},
                               {k: np.array(v) for k, v in camera.items()}, "image")
    variance = variance_test(d.ravel(), baseline.errors_px.ravel())
    criteria = _criteria(config, table, per_io, overall, corner_level + image_level, variance)
    return ProjectionResult(config, table, per_io, overall, corner_level + image_level,
                            baseline, variance, criteria, views, poses, render_seconds, 0.0)


def _criteria(config, table: CornerTable, per_io, overall, corrs: list[Correlation],
              variance: VarianceTest) -> list[Criterion]:
    out = []
    counted = [s for s in range(len(config.io_sets)) if np.any(table.io_set == s)]
    fractions = [float(table.found[table.io_set == s].mean()) for s in counted]
    worst = min(fractions) if fractions else 0.0
    out.append(Criterion(
        "corners found", "smallest fraction, over the cameras, of the measurable corners that "
        "the detector found within 2 px of their projection", round(worst, 4),
        f">= {MIN_FOUND_FRACTION}", worst >= MIN_FOUND_FRACTION))
    reach = [(abs(per_io[s][k].mean_px) + per_io[s][k].ci95_px, config.io_sets[s].name, k)
             for s in counted for k in ("dx", "dy", "dr") if per_io[s][k].n > 1]
    big = max(reach) if reach else (float("nan"), "-", "-")
    out.append(Criterion(
        "mean error 0 (each camera)", "largest |mean| + 95 % confidence half-width of dx, dy, "
        f"dr over the cameras ({big[2]}, {big[1]})", round(big[0], 5),
        f"<= {MAX_MEAN_CI_PX} px", bool(big[0] <= MAX_MEAN_CI_PX)))
    pooled = max(((abs(v.mean_px) + v.ci95_px, k) for k, v in overall.items()),
                 default=(float("nan"), "-"))
    out.append(Criterion(
        "mean error 0 (all)", f"|mean| + 95 % confidence half-width over all corners "
        f"(largest: {pooled[1]})", round(pooled[0], 5), f"<= {MAX_POOLED_MEAN_CI_PX} px",
        bool(pooled[0] <= MAX_POOLED_MEAN_CI_PX)))
    judged = [c for c in corrs
              if c.level == "corner" or c.n >= MIN_IMAGES_CAMERA_TEST]
    bad = [c for c in judged if c.p_bonferroni < ALPHA and abs(c.r) >= MIN_RELEVANT_R]
    strongest = max(judged, key=lambda c: abs(c.r)) if judged else None
    skipped = len(corrs) - len(judged)
    out.append(Criterion(
        "no correlation", "error against image position, radius and camera parameters: "
        "correlations both significant (Bonferroni-corrected p < 0.01) and not negligible "
        f"(|r| >= {MIN_RELEVANT_R}); strongest: "
        + (f"{strongest.error} vs {strongest.variable}, r = {strongest.r:.3f}, "
           f"p = {strongest.p_bonferroni:.3g}" if strongest else "none")
        + (f" (camera parameters not judged: fewer than {MIN_IMAGES_CAMERA_TEST} images)"
           if skipped else ""),
        len(bad), "0", not bad))
    same = variance.levene_p >= ALPHA or variance.excess_std_px <= MAX_EXCESS_STD_PX
    out.append(Criterion(
        "spread = detector's", f"rendered error std {variance.std_a_px:.4f} px vs detector "
        f"{variance.std_b_px:.4f} px on exact synthetic images: Levene p = "
        f"{variance.levene_p:.3g}; noise the renderer adds sqrt(var_r - var_d)",
        round(variance.excess_std_px, 4),
        f"Levene p >= {ALPHA} or <= {MAX_EXCESS_STD_PX} px", bool(same)))
    return out
