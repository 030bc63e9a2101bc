"""Texture validation: a texture keeps its resolution — no smoothing, edges in place.

Section 6.3 of the original study. A 1 m × 1 m plane carries a 10 × 10 black/white
checkerboard texture with one texel per square, so 1 texel = 10 cm. A nadir camera
(f = 10 mm, 10 µm pixels) 1 m above it has a ground sample distance of 1 mm: every
texel is seen as 100 × 100 px. The camera sits off the texel grid by a fraction of a
pixel, so texel edges fall inside pixels, not on their borders.

The expected image comes from the camera model alone: the plane's projection (a
homography) mapped through exact pixel-area integration (:mod:`designer.experiments.synthetic`)
or, without antialiasing, the texel under each pixel centre.

* 'Closest' texture interpolation without antialiasing: every pixel is pure black or
  white and has the colour of the texel under its centre, so every texel is 100 px wide
  and every edge is where the projection says to ±0.5 px;
* 'Closest' with the quality preset's antialiasing: pixels not crossed by a projected
  texel edge are pure; the crossed ones hold the area fraction the projection predicts,
  which places each edge to a small fraction of a pixel;
* 'Linear' interpolation, for contrast: it blends neighbouring texels over a whole texel
  (100 px), the smoothing the original study warns about.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.projection import R_cv_from_world
from designer.effects.srgb import decode_image, encode_image
from designer.experiments import figures
from designer.experiments.jobs import MeshObject, render_views
from designer.experiments.report import Criterion, Report, write_report
from designer.experiments.settings import RenderSettings, ValidationConfig
from designer.experiments.synthetic import coverage
from designer.render.job_spec import MaterialSpec
from designer.scene.texture import checkerboard_texture

TEXELS = 10
TEXEL_M = 0.1
SIZE_PX = (400, 300)
PITCH_MM = 0.01
FOCAL_MM = 10.0
HEIGHT_M = 1.0
#: the camera is this far (m) off a texel corner, so edges fall at 0.37 and 0.71 px
OFFSET_M = (0.00037, -0.00071)
#: each texel edge, located from the antialiased pixels along it, must lie within this (px)
MAX_EDGE_OFFSET_PX = 0.05


#: how the texture validation renders (settings, seed, workers), as every validation does
TextureConfig = ValidationConfig


def camera() -> InteriorOrientation:
    W, H = SIZE_PX
    return InteriorOrientation(FOCAL_MM, W * PITCH_MM, H * PITCH_MM, W, H)


def pose() -> tuple[np.ndarray, np.ndarray]:
    """Nadir camera (R = I: looking down, image top north) above a texel corner."""
    C = np.array([0.5 + OFFSET_M[0], 0.5 + OFFSET_M[1], HEIGHT_M])
    return C, np.eye(3)


def plane() -> MeshObject:
    """The 1 m × 1 m plane at Z = 0 with UV = (X, Y), textured 10 × 10 texels."""
    verts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    return MeshObject("plane", verts, np.array([[0, 1, 2, 3]]), uv=verts[:, :2].copy(),
                      materials=(MaterialSpec(texture="checker.png"),),
                      textures={"checker.png": checkerboard_texture(TEXELS, 1)})


def image_from_board() -> np.ndarray:
    """Homography board → pixels, board units = texels, board (x, y) = world (X, Y) / 0.1 m.

    The texture's top-left texel is black and texel (row r, column c) white when r + c is
    odd; rows count down from v = 1 (north), so the texel at board (x, y) is white when
    ⌊x⌋ + ⌊y⌋ is even — the complement of :func:`designer.experiments.synthetic.coverage`.
    """
    C, R = pose()
    interior = camera()
    return interior.K_px @ R_cv_from_world(R) @ np.column_stack(
        [[TEXEL_M, 0, 0], [0, TEXEL_M, 0], -C])


def expected_area() -> np.ndarray:
    """(H, W) white fraction of every pixel by exact area integration (linear)."""
    return 1.0 - coverage(image_from_board(), SIZE_PX)


def expected_point() -> np.ndarray:
    """(H, W) 1 where the texel under the pixel centre is white, else 0."""
    W, H = SIZE_PX
    Hinv = np.linalg.inv(image_from_board())
    v, u = np.mgrid[0:H, 0:W] + 0.5
    w = Hinv[2, 0] * u + Hinv[2, 1] * v + Hinv[2, 2]
    x = (Hinv[0, 0] * u + Hinv[0, 1] * v + Hinv[0, 2]) / w
    y = (Hinv[1, 0] * u + Hinv[1, 1] * v + Hinv[1, 2]) / w
    return ((np.floor(x) + np.floor(y)) % 2 == 0).astype(float)


def projected_edges() -> tuple[np.ndarray, np.ndarray]:
    """Texel edges in the image: u of the vertical ones, v of the horizontal ones (px)."""
    Hm = image_from_board()
    k = np.arange(-TEXELS, 2 * TEXELS, dtype=float)
    u = (Hm[0, 0] * k + Hm[0, 2]) / Hm[2, 2]
    v = (Hm[1, 1] * k + Hm[1, 2]) / Hm[2, 2]
    W, H = SIZE_PX
    return np.sort(u[(u > 0) & (u < W)]), np.sort(v[(v > 0) & (v < H)])


@dataclass
class TextureRender:
    name: str
    settings: RenderSettings
    codes: np.ndarray  # (H, W) uint8 as stored
    seconds: float

    @property
    def linear(self) -> np.ndarray:
        return decode_image(self.codes).astype(np.float64)

    @property
    def impure(self) -> np.ndarray:
        return (self.codes != 0) & (self.codes != 255)


def run_texture(config: TextureConfig, work_dir: Path) -> list[TextureRender]:
    s = config.settings
    todo = [("Closest, no antialiasing", RenderSettings(samples=1, filter_width_px=0.01)),
            (f"Closest, {s.label()}", s.with_(interpolation="Closest")),
            (f"Linear, {s.label()}", s.with_(interpolation="Linear"))]
    out = []
    for k, (name, settings) in enumerate(todo):
        views = render_views(work_dir / f"render-{k + 1}", [plane()], camera(), [pose()],
                             settings, seed=config.seed, workers=config.workers)
        out.append(TextureRender(name, settings, views.codes(0), views.seconds[0]))
    return out


def texel_widths_px(point_render: np.ndarray) -> np.ndarray:
    """Run lengths (px) of equal colour along the middle row and column, without the
    runs cut by the image border: the texel size in pixels."""
    runs = []
    H, W = point_render.shape
    for line in (point_render[H // 2], point_render[:, W // 2]):
        change = np.nonzero(np.diff(line.astype(int)))[0]
        runs += list(np.diff(change))
    return np.array(runs)


def edge_offsets_px(linear: np.ndarray, area: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position error (px) of every texel edge, and of every pixel along the edges.

    A vertical edge at u = e crosses column i = ⌊e⌋; a pixel there with white fraction V and
    white on its left puts the edge at i + V, with white on its right at i + 1 − V, so the
    edge's position error is ±(V − V_predicted). Pixels where two edges cross are skipped.
    Returns (mean error per edge, errors of all pixels used).
    """
    eu, ev = projected_edges()
    cols, rows = np.floor(eu).astype(int), np.floor(ev).astype(int)
    diff = linear - area
    per_edge, per_pixel = [], []
    for transpose in (False, True):
        d, a = (diff.T, area.T) if transpose else (diff, area)
        lines, others = (rows, cols) if transpose else (cols, rows)
        keep = np.ones(d.shape[0], bool)
        keep[others] = False
        keep[[0, -1]] = False
        for c in lines:
            if not 1 <= c < d.shape[1] - 1:
                continue
            white_left = a[keep, c - 1] > 0.5
            err = np.where(white_left, 1.0, -1.0) * d[keep, c]
            per_edge.append(err.mean())
            per_pixel.append(err)
    return np.array(per_edge), np.concatenate(per_pixel)


def judge(renders: list[TextureRender]) -> tuple[list[Criterion], dict]:
    point, aa, linear = renders
    want_point = encode_image(expected_point().astype(np.float32), np.uint8)
    area = expected_area()
    crossed = (area > 0) & (area < 1)
    pure_expected = ~crossed
    aa_err = np.abs(aa.linear - area)
    edge_offsets, pixel_offsets = edge_offsets_px(aa.linear, area)
    # Cycles puts the first of a pixel's N samples at its centre: the expected value of an
    # edge pixel is (centre colour + (N − 1) · area) / N, not the area.
    n = aa.settings.samples
    centre_model, _ = edge_offsets_px((expected_point() + (n - 1) * area) / n, area)
    widths = texel_widths_px(point.codes)
    figures_ = {
        "point_impure": int(point.impure.sum()),
        "point_wrong": int((point.codes != want_point).sum()),
        "aa_impure_off_edges": int((aa.impure & pure_expected).sum()),
        "aa_wrong_off_edges": int((np.abs(aa.linear - area) > 0.5)[pure_expected].sum()),
        "aa_edge_pixels": int(crossed.sum()),
        "aa_impure": int(aa.impure.sum()),
        "aa_edge_error_mean": float(aa_err[crossed].mean()),
        "aa_edge_error_max": float(aa_err[crossed].max()),
        "aa_edge_offsets_px": edge_offsets.round(5).tolist(),
        "aa_edge_offsets_centre_sample_model_px": centre_model.round(5).tolist(),
        "aa_edge_offset_max_px": float(np.abs(edge_offsets).max()),
        "aa_edge_pixel_std_px": float(pixel_offsets.std(ddof=1)),
        "linear_impure": int(linear.impure.sum()),
        "linear_impure_off_edges": int((linear.impure & pure_expected).sum()),
        "pixels": int(area.size),
        "texel_widths_px": sorted(set(widths.tolist())),
    }
    criteria = [
        Criterion("Closest, no AA: pure", "pixels that are not pure black (0) or white (255)",
                  figures_["point_impure"], "0", figures_["point_impure"] == 0),
        Criterion("Closest, no AA: in place", "pixels whose colour differs from the texel the "
                  "projection puts under the pixel centre (edges to ±0.5 px)",
                  figures_["point_wrong"], "0", figures_["point_wrong"] == 0),
        Criterion("texel = 100 px", "widths of whole texels along the middle row and column (px)",
                  ", ".join(map(str, figures_["texel_widths_px"])), "100",
                  figures_["texel_widths_px"] == [100]),
        Criterion("Closest, antialiased: pure off edges", "pixels not crossed by a projected "
                  "texel edge that are not pure black or white",
                  figures_["aa_impure_off_edges"], "0", figures_["aa_impure_off_edges"] == 0),
        Criterion("Closest, antialiased: edges in place", "largest |position error| of a texel "
                  "edge located from the white fraction of the pixels along it, against its "
                  "projection", round(figures_["aa_edge_offset_max_px"], 4),
                  f"<= {MAX_EDGE_OFFSET_PX} px",
                  figures_["aa_edge_offset_max_px"] <= MAX_EDGE_OFFSET_PX),
    ]
    return criteria, figures_


def write_texture_report(renders, criteria, numbers, out_dir: Path, config: TextureConfig,
                         wall_seconds: float) -> dict:
    eu, ev = projected_edges()
    views = figures.texture_views(
        out_dir / "texture-views.png",
        [(r.name, r.codes) for r in renders], eu, ev)
    W, H = SIZE_PX
    u0 = int(np.floor(eu[0])) - 6
    row = int((ev[len(ev) // 2 - 1] + ev[len(ev) // 2]) / 2)  # mid-texel: Linear's full ramp
    prof = figures.profile(out_dir / "texture-profile.png",
                           [(r.name, r.codes[row, u0:u0 + 13].astype(float)) for r in renders],
                           eu, u0, f"Row {row}: 13 pixels across a texel edge")
    zoom = figures.profile(out_dir / "texture-profile-wide.png",
                           [(r.name, r.codes[row, 0:W].astype(float)) for r in renders],
                           eu, 0, f"Row {row}, the whole width ({W} px)")
    r = Report("Validation 3: texture resolution")
    passed = r.opening(
        criteria,
        "**Question.** Does the renderer keep a texture's resolution? Texture interpolation "
        "can smooth a texture (each pixel blends neighbouring texels) so that the images hold "
        "less detail than the texture has, and edges move. For geometric experiments a texel "
        "must stay a sharp-edged square of the right size in the right place.")
    r.bullets([
        f"**Scene.** A 1 m × 1 m plane with a {TEXELS} × {TEXELS} black/white checkerboard "
        f"texture, one texel per square: 1 texel = {TEXEL_M * 100:g} cm.",
        f"**Camera.** {W} × {H} px, {PITCH_MM * 1000:g} µm pixels, {FOCAL_MM:g} mm lens, "
        f"looking straight down from {HEIGHT_M:g} m: a ground sample distance of 1 mm, so "
        f"a texel is seen as 100 × 100 px. The camera is {OFFSET_M[0] * 1000:g} mm, "
        f"{OFFSET_M[1] * 1000:g} mm off a texel corner so the edges cross pixels at "
        f"fractions of a pixel, not along pixel borders.",
        "**Expected image.** From the camera model alone: without antialiasing, the colour "
        "of the texel under each pixel centre; with antialiasing, the exact fraction of each "
        "pixel's area that is white (the plane's projection, clipped pixel by pixel).",
        "**Renders.** 'Closest' texture interpolation without antialiasing (one sample at "
        f"each pixel centre), 'Closest' with the quality preset ({config.settings.label()}), "
        "and 'Linear' interpolation with the same preset, for contrast.",
    ])
    r.heading("Criteria")
    r.criteria(criteria)
    r.heading("What the renders contain")
    n = numbers
    r.table(["render", "pixels not pure black/white", "… of them off the projected edges",
             "seconds"],
            [[renders[0].name, n["point_impure"], n["point_impure"], f"{renders[0].seconds:.2f}"],
             [renders[1].name, n["aa_impure"], n["aa_impure_off_edges"],
              f"{renders[1].seconds:.2f}"],
             [renders[2].name, n["linear_impure"], n["linear_impure_off_edges"],
              f"{renders[2].seconds:.2f}"]])
    r.para(f"Of {n['pixels']} pixels, {n['aa_edge_pixels']} are crossed by a projected texel "
           f"edge. In those, the antialiased 'Closest' render differs from the predicted white "
           f"fraction by {n['aa_edge_error_mean']:.4f} on average and {n['aa_edge_error_max']:.4f} "
           "at most. For an edge parallel to the pixel grid this difference is where the pixel "
           "puts the edge, in pixels: one pixel places it to "
           f"±{n['aa_edge_pixel_std_px']:.3f} px (std; the sampling noise of "
           f"{renders[1].settings.samples} samples), and the pixels along each edge together "
           "place the edges at offsets of "
           + ", ".join(f"{x:+.4f}" for x in n["aa_edge_offsets_px"]) + " px from their "
           "projections.")
    r.para(
        "These small offsets are not a geometric error but a property of Cycles' sampling, "
        "measured here: the first of the N samples of every pixel lies exactly at the pixel "
        "centre (with 1 sample per pixel the image is point-sampled), so an edge pixel's value "
        "is (colour at its centre + (N − 1) × area) / N rather than the area alone. The "
        f"edges here cross their pixels at the same fraction ({eu[0] % 1:.2f} px and "
        f"{ev[0] % 1:.2f} px), so that "
        "pulls every edge the same way, by (centre − area)/N: for N = "
        f"{renders[1].settings.samples} that model predicts offsets of "
        + ", ".join(f"{x:+.4f}" for x in n["aa_edge_offsets_centre_sample_model_px"])
        + " px. Over edges at random sub-pixel positions (as in the projection validation) "
        "the effect averages out and only adds spread; it shrinks as 1/N.")
    r.figure(views.name, "The three renders; dashed red lines: texel edges projected by the "
             "camera model.")
    r.figure(prof.name, "Pixel values across one texel edge: 'Closest' changes within one "
             "pixel (the one the edge crosses), exactly at the projected edge.")
    r.figure(zoom.name, "The same row across the whole image: 'Linear' interpolation turns "
             "every texel into a ramp 100 px long — it smooths the texture over a whole texel.")
    r.para(
        "**Reading.** With 'Closest' the texture is reproduced at full resolution: pure black "
        "and white texels of 100 × 100 px whose edges lie where the camera model projects "
        "them, with antialiasing blending only the single pixel an edge crosses, in exactly "
        "the proportion of its area. 'Linear' interpolation blends texel colours over the "
        "distance between texel centres, so a texture seen larger than one pixel per texel "
        "is blurred; designer uses 'Closest' unless a project asks otherwise, and textures "
        "should have texels no larger than half the ground sample distance.")
    r.heading("Reproduce")
    r.para(f"`designer validate texture -o DIR` ({wall_seconds:.0f} s).")
    summary = {"experiment": "texture", "passed": passed, "criteria": criteria,
               "settings": config.settings.to_dict(), "numbers": numbers,
               "renders": [{"name": x.name, "settings": x.settings.to_dict(),
                            "seconds": x.seconds} for x in renders],
               "wall_seconds": wall_seconds,
               "figures": {"views": views.name, "profile": prof.name, "row": zoom.name}}
    write_report(out_dir, r, summary)
    return summary


def validate_texture(config: TextureConfig, out_dir: Path) -> dict:
    """Run the texture validation and write its report into ``out_dir``; return the summary."""
    t0 = time.perf_counter()
    renders = run_texture(config, out_dir / "renders")
    criteria, numbers = judge(renders)
    return write_texture_report(renders, criteria, numbers, out_dir, config,
                                time.perf_counter() - t0)
