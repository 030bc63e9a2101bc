"""The dome of a self-calibrated flat block, nadir against convergent (``designer bench
doming``): James & Robson (2014) on a synthetic block, through designer's own processing.

No render and no feature matching: a flat field (Z = 0) of random tie points under a
grid flight of a 640 × 480 px camera (f 500 px, k1 −0.08, k2 0.01) at 30 m over a
60 × 60 m area (front 80 %, side 65 %: 80 images, GSD 6 cm), flown either **nadir**
(parallel axes) or **convergent** (the camera tilted 20° forward, so the view
alternates with the line direction), each tie point's image positions with Gaussian
noise (0.3 px, about what SIFT gives on these renders). Each replicate draws the noise
and the pre-calibration error (σ 5 px in f, 0.02 in k1) and is processed as
``designer reconstruct --mode free --calibration radial --gcps similarity`` processes a
survey:

1. the mapper's structure: a bundle adjustment refining what the incremental mapper
   refines for the calibration mode (designer.sfm.mapping.mapper_refines: the
   focal length; the distortion stays at the pre-calibration), so the wrong k1 is
   absorbed by the structure as it is in SfM;
2. the final adjustment with self-calibration (designer.sfm.adjustment.adjust);
3. a similarity of the points onto the truth (the GCP similarity, with every point as
   control), then the dome: the points' height errors gridded as a DoD and fitted over
   the flown area, as the dense stage fits a survey's
   (designer.evaluate.raster_products.dome_over_area).

Rows per geometry: the dome (GSD) of each replicate, the mean |dome|, the focal length
and k1 errors, and the "k1 error beyond the focal trade": on flat ground under parallel
axes a camera of focal length c·f and radial terms c²·k1, c⁴·k2, c⁶·k3 images the plane
exactly as the true one from c times the height (the exact degeneracy), so only
k1 − c²·k1_true can bend the surface. The **prediction** row: the dome that a fixed k1
error of +0.01 gives each geometry (a fixed camera, nothing else wrong) — the dome per
unit of k1 error; the first-order estimate δk1 · D² / (4 H) for a block of width D flown
at H (a paraboloid of curvature 2 δk1 / H, the across-track parallax error of a radial
error, peak to edge) gives 0.30 m = 5 GSD here.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from designer.bench.synthetic_block import add_noisy_image, add_tracks


@dataclass(frozen=True)
class FlatBlock:
    """A synthetic flat block (module docstring); lengths in m, image sizes in px."""

    half_width_m: float = 30.0
    height_m: float = 30.0
    front_overlap: float = 0.80
    side_overlap: float = 0.65
    points: int = 3000
    noise_px: float = 0.3
    width_px: int = 640
    height_px: int = 480
    focal_px: float = 500.0
    k1: float = -0.08
    k2: float = 0.01
    pre_focal_sigma_px: float = 5.0
    pre_k1_sigma: float = 0.02
    gsd_m: float = 0.06
    dome_cell_m: float = 3.0

    def true_params(self) -> np.ndarray:
        """FULL_OPENCV parameters of the true camera."""
        p = np.zeros(12)
        p[:6] = (self.focal_px, self.focal_px, self.width_px / 2, self.height_px / 2,
                 self.k1, self.k2)
        return p


#: the block of the guard test: the same geometry with fewer tie points
SMALL = FlatBlock(points=1500)
#: the geometries compared: forward tilt of the camera, deg
GEOMETRIES = {"nadir": 0.0, "convergent": 20.0}


@dataclass(frozen=True)
class BlockResult:
    """One processed replicate: the dome over the flown area (GSD, dome > 0, bowl < 0),
    the estimated − true focal length (px) and k1, the k1 error beyond the focal trade,
    RMS of the height errors (GSD) and the final adjustment's termination."""

    geometry: str
    seed: int
    dome_gsd: float
    focal_error_px: float
    k1_error: float
    k1_error_beyond_focal: float
    rms_z_gsd: float
    termination: str


def cam_from_world(heading_sign: float, tilt_deg: float) -> np.ndarray:
    """CV-frame rotation (world → camera) of a camera flying north (+1) or south (−1)
    with the image top ahead, tilted ``tilt_deg`` forward from nadir."""
    s, c = np.sin(np.radians(tilt_deg)), np.cos(np.radians(tilt_deg))
    z = np.array([0.0, heading_sign * s, -c])  # viewing direction
    x = np.array([heading_sign, 0.0, 0.0])  # image right
    return np.stack([x, np.cross(z, x), z])


def project_px(params: np.ndarray, R: np.ndarray, C: np.ndarray, X: np.ndarray):
    """(uv (N, 2) px with OpenCV's radial distortion, depth (N,)) of world points X."""
    p = (X - C) @ R.T
    z = p[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        x, y = p[:, 0] / z, p[:, 1] / z
    r2 = x * x + y * y
    d = 1 + params[4] * r2 + params[5] * r2 * r2 + params[8] * r2 ** 3
    return np.stack([params[0] * x * d + params[2], params[1] * y * d + params[3]], 1), z


def stations(block: FlatBlock, tilt_deg: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """(centre, cam_from_world) of each photo: north-south lines flown alternately north
    and south, each camera's ground point of view on the planned grid."""
    foot_x = block.height_m * block.width_px / block.focal_px
    foot_y = block.height_m * block.height_px / block.focal_px
    xs = np.arange(-block.half_width_m, block.half_width_m + 1e-6,
                   foot_x * (1 - block.side_overlap))
    ys = np.arange(-block.half_width_m - foot_y / 2, block.half_width_m + foot_y / 2 + 1e-6,
                   foot_y * (1 - block.front_overlap))
    xs, ys = xs - xs.mean(), ys - ys.mean()
    lead = block.height_m * np.tan(np.radians(tilt_deg))
    out = []
    for i, x in enumerate(xs):
        sign = 1.0 if i % 2 == 0 else -1.0
        for y in ys if sign > 0 else ys[::-1]:
            out.append((np.array([x, y - sign * lead, block.height_m]),
                        cam_from_world(sign, tilt_deg)))
    return out


def synthetic_block(block: FlatBlock, tilt_deg: float, seed: int):
    """(reconstruction at the start of processing, true point by point id) of one
    replicate: the camera at its drawn pre-calibration, poses and points slightly off."""
    import pycolmap

    rng = np.random.default_rng(seed)
    true = block.true_params()
    margin = block.height_m * 0.8
    lim = block.half_width_m + margin
    pts = np.column_stack([rng.uniform(-lim, lim, block.points),
                           rng.uniform(-lim, lim, block.points), np.zeros(block.points)])
    start = true.copy()
    start[0] = start[1] = true[0] + rng.normal(0.0, block.pre_focal_sigma_px)
    start[4] += rng.normal(0.0, block.pre_k1_sigma)
    W, H = block.width_px, block.height_px
    rec = pycolmap.Reconstruction()
    rec.add_camera_with_trivial_rig(pycolmap.Camera(
        model="FULL_OPENCV", width=W, height=H, params=start, camera_id=1))
    seen: dict[int, list[tuple[int, int]]] = {}
    for k, (C, R) in enumerate(stations(block, tilt_deg)):
        uv, depth = project_px(true, R, C, pts)
        inside = np.flatnonzero((depth > 0) & (uv[:, 0] > 1) & (uv[:, 0] < W - 1)
                                & (uv[:, 1] > 1) & (uv[:, 1] < H - 1))
        add_noisy_image(rec, rng, k + 1, f"IMG_{k:04d}", uv[inside], inside, block.noise_px,
                        C, R, seen)
    return rec, add_tracks(rec, seen, pts, rng)


def mapper_structure(rec, calibration: str) -> None:
    """Adjust ``rec`` in place as the incremental mapper's adjustments do: the interior
    parameters designer's mapper refines for ``calibration``, the gauge on two cameras."""
    import pycolmap

    from designer.sfm.mapping import mapper_refines

    options = pycolmap.BundleAdjustmentOptions()
    (options.refine_focal_length, options.refine_principal_point,
     options.refine_extra_params) = mapper_refines(calibration)
    options.print_summary = False
    config = pycolmap.BundleAdjustmentConfig()
    for image_id in rec.reg_image_ids():
        config.add_image(image_id)
    config.fix_gauge(pycolmap.BundleAdjustmentGauge.TWO_CAMS_FROM_WORLD)
    pycolmap.create_default_ceres_bundle_adjuster(options, config, rec).solve()


def similarity_onto(src: np.ndarray, tgt: np.ndarray) -> np.ndarray:
    """``src`` (N, 3) mapped by the least-squares similarity onto ``tgt`` (Umeyama; the
    robust similarity of designer.sfm.georeference.fit_similarity finds none for a block
    whose true points lie exactly in one plane)."""
    ms, mt = src.mean(axis=0), tgt.mean(axis=0)
    a, b = src - ms, tgt - mt
    U, S, Vt = np.linalg.svd(b.T @ a / len(src))
    D = np.eye(3)
    D[2, 2] = np.sign(np.linalg.det(U @ Vt))
    R = U @ D @ Vt
    scale = np.trace(np.diag(S) @ D) / a.var(axis=0).sum()
    return scale * a @ R.T + mt


def block_dome(rec, truth: dict, block: FlatBlock):
    """(dome fit of the height errors over the flown area, RMS of the height errors
    there in GSD) after the similarity of the points onto the truth: the points' height
    errors gridded as a DoD and fitted over the flight's area as the dense stage fits a
    survey's (designer.evaluate.raster_products.dome_over_area)."""
    from designer.evaluate.raster_products import dome_over_area
    from designer.evaluate.rasters import dsm_from_points

    ids = list(truth)
    true = np.array([truth[i] for i in ids])
    est = similarity_onto(np.array([rec.points3D[i].xyz for i in ids]), true)
    dz = est[:, 2] - true[:, 2]
    h = block.half_width_m
    area = np.array([[-h, -h], [h, -h], [h, h], [-h, h]])
    dod = dsm_from_points(np.column_stack([true[:, :2], dz]), block.dome_cell_m)
    fit, where = dome_over_area(dod, block.gsd_m, area)
    if where != "the survey area":
        raise RuntimeError(f"the synthetic block's DoD holds too few cells over its area ({where})")
    inside = (np.abs(true[:, 0]) <= h) & (np.abs(true[:, 1]) <= h)
    return fit, float(np.sqrt(np.mean(dz[inside] ** 2)) / block.gsd_m)


def process_replicate(block: FlatBlock, geometry: str, seed: int,
                      calibration: str = "radial") -> BlockResult:
    """One replicate of ``geometry`` processed as the module docstring says."""
    from designer.sfm.adjustment import adjust

    rec, truth = synthetic_block(block, GEOMETRIES[geometry], seed)
    mapper_structure(rec, calibration)
    result = adjust(rec, calibration)
    fit, rms = block_dome(rec, truth, block)
    est, true = np.asarray(rec.cameras[1].params, float), block.true_params()
    c = est[0] / true[0]
    return BlockResult(geometry, seed, float(fit.amplitude_gsd), float(est[0] - true[0]),
                       float(est[4] - true[4]), float(est[4] - c * c * true[4]), rms,
                       result.termination)


def fixed_k1_dome_gsd(block: FlatBlock, geometry: str, k1_error: float = 0.01) -> float:
    """The dome (GSD) of ``geometry`` processed with the camera fixed at the true one
    but for ``k1_error``: the dome per unit of k1 error (no pre-calibration draw, no
    self-calibration)."""
    from designer.sfm.adjustment import adjust

    exact = replace(block, pre_focal_sigma_px=0.0, pre_k1_sigma=0.0)
    rec, truth = synthetic_block(exact, GEOMETRIES[geometry], seed=0)
    params = np.asarray(rec.cameras[1].params, float).copy()
    params[4] += k1_error
    rec.cameras[1].params = params
    adjust(rec, "fixed")
    return float(block_dome(rec, truth, exact)[0].amplitude_gsd)


def compare_geometries(block: FlatBlock, replicates: int,
                       calibration: str = "radial") -> dict[str, list[BlockResult]]:
    """Every geometry's replicates (seeds 0 … replicates − 1)."""
    return {g: [process_replicate(block, g, s, calibration) for s in range(replicates)]
            for g in GEOMETRIES}


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    """Rows: each geometry's replicates (``repeats`` of them, at least 3) and the
    fixed-k1 prediction; ``scale`` < 1 thins the tie points (tests)."""
    block = FlatBlock() if scale >= 1.0 else replace(
        FlatBlock(), points=max(800, round(FlatBlock().points * scale)))
    replicates = max(3, repeats)
    rows = []
    for geometry in GEOMETRIES:
        t = time.perf_counter()
        results = [process_replicate(block, geometry, s) for s in range(replicates)]
        seconds = time.perf_counter() - t
        for r in results:
            rows.append({"figure": f"{geometry}, replicate {r.seed}: dome", "value":
                         f"{r.dome_gsd:+.2f} GSD (Δf {r.focal_error_px:+.1f} px, Δk1 "
                         f"{r.k1_error:+.4f}, beyond the focal trade "
                         f"{r.k1_error_beyond_focal:+.4f}; "
                         f"RMS Z {r.rms_z_gsd:.2f} GSD)"})
        rows.append({"figure": f"{geometry}: mean |dome| over {replicates} replicates",
                     "value": f"{np.mean([abs(r.dome_gsd) for r in results]):.2f} GSD "
                              f"({seconds:.0f} s)"})
        rows.append({"figure": f"{geometry}: dome of a fixed k1 error of +0.01 (prediction)",
                     "value": f"{fixed_k1_dome_gsd(block, geometry):+.2f} GSD"})
    return rows


def format_table(rows: list[dict]) -> str:
    width = max(len(r["figure"]) for r in rows)
    lines = [f"{'figure':<{width}}  value", "-" * (width + 40)]
    lines += [f"{r['figure']:<{width}}  {r['value']}" for r in rows]
    lines.append("(synthetic flat block, 60 x 60 m at 30 m, 80 images, GSD 6 cm; radial "
                 "self-calibration from a drawn pre-calibration, the GCP similarity; "
                 "docs/studies.md, 'Doming')")
    return "\n".join(lines)
