"""Point-spread validation: a sphere inside one pixel's viewing cone lights only that pixel.

Section 6.2 of the original study. A white (emissive) sphere on the optical axis, 100 m
from a camera with 1000 px focal length, is sized so that its image is a disc of radius
0.3 px in the middle of the centre pixel of a 33 × 33 px image: the whole sphere lies
inside that pixel's viewing cone. Rendered

* without antialiasing (one sample at each pixel centre: a 0.01 px box filter), the
  centre pixel is white and every other pixel exactly 0;
* with designer's antialiasing (the quality preset's 1 px box filter: each pixel
  integrates exactly its own area; rendered with 1024 samples so that the area is
  measured precisely, and with the preset's own samples), the centre pixel holds the
  disc's area (0.283 of a pixel) and every other pixel is still exactly 0: the
  point-spread function is the pixel itself;
* with Blender's default filter (Blackman–Harris, 1.5 px) and a Gaussian (1.5 px) for
  contrast: samples are shared with the neighbours, so the sphere leaks into them —
  the blur the original study saw.

Images are written as 16-bit PNG so that a leak of 1e-6 of the white level shows.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.experiments import figures
from designer.experiments.jobs import MeshObject, render_views
from designer.experiments.report import Criterion, Report, write_report
from designer.experiments.settings import RenderSettings, ValidationConfig
from designer.render.job_spec import MaterialSpec

SIZE_PX = 33
FOCAL_PX = 1000.0
DISTANCE_M = 100.0
DISC_RADIUS_PX = 0.3
#: a leak below this (linear, fraction of white) would be invisible even in 16 bits
ZERO = 0.0
#: the antialiased centre pixel must hold the disc's area to within this (fraction of white)
AREA_TOLERANCE = 0.03


#: how the PSF validation renders (settings, seed, workers), as every validation does
PSFConfig = ValidationConfig


def camera() -> InteriorOrientation:
    """33 × 33 px, 0.1 mm pixels, 100 mm lens (fx = 1000 px), principal point at the centre.

    (Blender clamps a sensor narrower than 1 mm to 1 mm, so the pixels are large.)
    """
    pitch_mm = 0.1
    return InteriorOrientation(FOCAL_PX * pitch_mm, SIZE_PX * pitch_mm, SIZE_PX * pitch_mm,
                               SIZE_PX, SIZE_PX)


def sphere_radius_m() -> float:
    """Radius whose silhouette seen from DISTANCE_M is a disc of DISC_RADIUS_PX (on axis:
    tan(asin(ρ / D)) · f = r)."""
    t = DISC_RADIUS_PX / FOCAL_PX
    return DISTANCE_M * t / math.sqrt(1 + t * t)


def sphere(segments: int = 128) -> MeshObject:
    """A UV sphere about the optical axis (poles on it), so its silhouette is the equator:
    a regular polygon of ``segments`` sides."""
    rho = sphere_radius_m()
    rings = segments // 2
    theta = np.linspace(0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                     np.repeat(np.cos(theta)[:, None], segments, 1)], -1).reshape(-1, 3)
    verts = np.vstack([[0, 0, 1], ring, [0, 0, -1]]) * rho + [0, 0, -DISTANCE_M]
    faces = []
    n = segments
    last = 1 + (rings - 2) * n
    for k in range(n):
        faces.append([0, 1 + k, 1 + (k + 1) % n])
        faces.append([len(verts) - 1, last + (k + 1) % n, last + k])
    for r in range(rings - 2):
        for k in range(n):
            a, b = 1 + r * n + k, 1 + r * n + (k + 1) % n
            faces += [[a, a + n, b + n], [a, b + n, b]]
    return MeshObject("sphere", verts, np.array(faces),
                      materials=(MaterialSpec(color=(1.0, 1.0, 1.0)),))


def expected_disc_area_px(segments: int = 128) -> float:
    """Area (px²) of the silhouette: the equator polygon projected (the true silhouette of
    the polygonal sphere differs by < 1e-7 px² at this distance)."""
    r = DISC_RADIUS_PX
    return 0.5 * segments * r * r * math.sin(2 * math.pi / segments)


@dataclass
class PSFVariant:
    name: str
    settings: RenderSettings
    image: np.ndarray  # (H, W) linear
    seconds: float

    @property
    def centre(self) -> float:
        c = SIZE_PX // 2
        return float(self.image[c, c])

    @property
    def neighbours(self) -> float:
        """Energy in the 8 pixels around the centre pixel."""
        c = SIZE_PX // 2
        return float(self.image[c - 1:c + 2, c - 1:c + 2].sum() - self.image[c, c])

    @property
    def elsewhere(self) -> float:
        """Energy in all pixels but the centre one."""
        return float(self.image.sum() - self.centre)

    @property
    def centre_fraction(self) -> float:
        total = float(self.image.sum())
        return self.centre / total if total > 0 else math.nan


#: samples for the filter comparisons: the PSF is the filter's; samples only cut noise
FILTER_SAMPLES = 1024


def variants(settings: RenderSettings) -> list[tuple[str, RenderSettings]]:
    """(name, settings) of the renders: no antialiasing, the preset's filter with many
    samples, the preset itself, and two wide filters for contrast."""
    many = RenderSettings(samples=FILTER_SAMPLES)
    filt = f"{settings.pixel_filter.lower().replace('_', '-')} {settings.filter_width_px:g} px"
    return [
        ("no antialiasing: 1 sample at each pixel centre",
         RenderSettings(samples=1, filter_width_px=0.01)),
        (f"designer's filter ({filt}), {FILTER_SAMPLES} spp",
         many.with_(pixel_filter=settings.pixel_filter, filter_width_px=settings.filter_width_px)),
        (f"quality preset as used ({settings.label()})", settings),
        (f"Blender's default filter (Blackman-Harris 1.5 px), {FILTER_SAMPLES} spp",
         many.with_(pixel_filter="BLACKMAN_HARRIS", filter_width_px=1.5)),
        (f"Gaussian 1.5 px, {FILTER_SAMPLES} spp",
         many.with_(pixel_filter="GAUSSIAN", filter_width_px=1.5)),
    ]


def run_psf(config: PSFConfig, work_dir: Path) -> tuple[list[PSFVariant], list[Criterion]]:
    interior = camera()
    pose = [(np.zeros(3), np.eye(3))]  # at the origin looking along −z
    out = []
    for k, (name, settings) in enumerate(variants(config.settings)):
        views = render_views(work_dir / f"variant-{k + 1}", [sphere()], interior, pose, settings,
                             seed=config.seed, bit_depth=16, workers=config.workers)
        out.append(PSFVariant(name, settings, views.linear(0).astype(np.float64),
                              views.seconds[0]))
    point, designer, preset = out[0], out[1], out[2]
    area = expected_disc_area_px()
    criteria = [
        Criterion("no antialiasing: centre white", "centre pixel value (white = 1)",
                  round(point.centre, 6), "= 1", point.centre == 1.0),
        Criterion("no antialiasing: others 0", "energy in all other pixels",
                  point.elsewhere, "= 0", point.elsewhere == ZERO),
        Criterion("antialiased: others 0", f"energy outside the centre pixel, {designer.name}",
                  designer.elsewhere, "= 0", designer.elsewhere == ZERO),
        Criterion("antialiased: disc area", "centre pixel value vs the disc's area "
                  f"{area:.4f} px² (exact area sampling)", round(designer.centre, 4),
                  f"{area:.4f} ± {AREA_TOLERANCE}", abs(designer.centre - area) <= AREA_TOLERANCE),
        Criterion("preset: others 0", f"energy outside the centre pixel, {preset.name}",
                  preset.elsewhere, "= 0", preset.elsewhere == ZERO),
    ]
    return out, criteria


def write_psf_report(result: list[PSFVariant], criteria: list[Criterion], out_dir: Path,
                     config: PSFConfig, wall_seconds: float) -> dict:
    c = SIZE_PX // 2
    fig = figures.pixel_grids(out_dir / "psf-pixels.png",
                              [(_wrap(v.name), v.image) for v in result], (c, c))
    r = Report("Validation 2: point-spread function")
    passed = r.opening(
        criteria,
        "**Question.** Does the renderer blur? A point that lies inside one pixel's field of "
        "view must light that pixel and no other — the point-spread function must be the "
        "pixel itself. Antialiasing filters that share samples between neighbouring pixels "
        "(Blender's default) spread light into the neighbours; the original study saw this.")
    r.bullets([
        f"**Camera.** {SIZE_PX} × {SIZE_PX} px, focal length {FOCAL_PX:g} px "
        f"({camera().focal_length_mm:g} mm lens, {camera().pixel_pitch_x_mm * 1000:g} µm "
        "pixels), principal point at the image centre, looking along the optical axis.",
        f"**Sphere.** A white emissive sphere of radius {sphere_radius_m() * 1000:.2f} mm "
        f"centred on the optical axis {DISTANCE_M:g} m away: its image is a disc of radius "
        f"{DISC_RADIUS_PX} px ({expected_disc_area_px():.4f} px²) in the middle of pixel "
        f"({c}, {c}), which spans 1 px. Black background.",
        "**Renders.** 16-bit PNG (a leak of 1e-6 of white would show), decoded to linear "
        "light. 'No antialiasing' is one sample at each pixel centre (box filter 0.01 px wide); "
        "'designer' is the quality preset, whose 1 px box filter integrates exactly each "
        "pixel's own area.",
    ])
    r.heading("Criteria")
    r.criteria(criteria)
    r.heading("Energy per pixel (white = 1)")
    r.table(["render", "centre pixel", "8 neighbours", "all other pixels",
             "share of energy in the centre pixel", "seconds"],
            [[v.name, f"{v.centre:.5f}", f"{v.neighbours:.5g}", f"{v.elsewhere:.5g}",
              f"{v.centre_fraction:.4f}", f"{v.seconds:.2f}"] for v in result])
    r.figure(fig.name, "The 7 × 7 pixels around the sphere in each render, with their linear "
             "values.")
    r.para(
        "**Reading.** Without antialiasing the sphere is a single white pixel: the sample at "
        "its centre hits the sphere, the samples of all other pixels miss it. With designer's "
        "1 px box filter every sample of a pixel stays inside that pixel, so the centre pixel "
        "measures the disc's area and the neighbours stay exactly 0 — antialiasing without "
        "blur. Blackman–Harris and Gaussian filters 1.5 px wide take a pixel's samples from "
        "beyond its edges, so they spread the sphere over the neighbours: use them only when a "
        "smooth, camera-like PSF is wanted, not for geometric validation.")
    r.para(
        "The antialiased centre pixel reads slightly more than the disc's area because Cycles "
        "puts the first of a pixel's N samples exactly at its centre (at 1 sample per pixel "
        "the image is point-sampled; see the texture validation), which here always hits the "
        "sphere: the expected value is (1 + (N − 1) × area) / N, "
        f"{(1 + (FILTER_SAMPLES - 1) * expected_disc_area_px()) / FILTER_SAMPLES:.4f} for "
        f"N = {FILTER_SAMPLES} and {(1 + 63 * expected_disc_area_px()) / 64:.4f} for N = 64; "
        "the rest is sampling noise.")
    r.heading("Reproduce")
    r.para(f"`designer validate psf -o DIR` ({wall_seconds:.0f} s).")
    summary = {"experiment": "psf", "passed": passed, "criteria": criteria,
               "settings": config.settings.to_dict(),
               "disc_area_px2": expected_disc_area_px(),
               "renders": [{"name": v.name, "settings": v.settings.to_dict(),
                            "centre": v.centre, "neighbours": v.neighbours,
                            "elsewhere": v.elsewhere, "centre_fraction": v.centre_fraction,
                            "seconds": v.seconds} for v in result],
               "wall_seconds": wall_seconds, "figures": {"pixels": fig.name}}
    write_report(out_dir, r, summary)
    return summary


def _wrap(text: str, width: int = 40) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width))


def validate_psf(config: PSFConfig, out_dir: Path) -> dict:
    """Run the PSF validation and write its report into ``out_dir``; return the summary."""
    t0 = time.perf_counter()
    result, criteria = run_psf(config, out_dir / "renders")
    return write_psf_report(result, criteria, out_dir, config, time.perf_counter() - t0)
