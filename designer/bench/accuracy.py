"""What geometric accuracy costs in render time (``designer bench accuracy``).

The projection experiment of ``designer validate projection`` (checkerboard corners in the
10 m cube, Harris + cornerSubPix against the camera model), run on the same poses with
each setting that trades time for accuracy: samples per pixel, adaptive sampling, pixel
filter type and width, oversampling (render k× larger, average in linear light), texture
interpolation, and oversampling of the distortion warp. For every setting: Cycles seconds
per output megapixel (the render call, and the CPU time of the worker processes, which
machine load disturbs less) against the corner error's standard deviation and bias.

The same poses and corners are measured in every row, so the detector's own error — the
same in every row — cancels out of the comparison; what differs is what the renderer does.
Plain 64 spp is rendered first and last and its mean time is the reference ("× plain 64").
The quality presets (``designer.experiments.settings.QUALITY_PRESETS``) are the cheapest
measured settings at least as accurate as plain 4, 16 and 64 spp — the old presets — and
the table marks the Pareto front (no other setting is both faster and more accurate).

The plot and a JSON copy of the table go to ``bench-accuracy/`` in the current folder.
"""

from __future__ import annotations

import json
import os
import tempfile
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.core.distortion import BrownConrady
from designer.effects.distortion_render import pinhole_render_camera
from designer.effects.srgb import encode_image
from designer.experiments.corners import Detector
from designer.experiments.cube import cube_corners, cube_walls, measurable, random_poses
from designer.experiments.jobs import render_views
from designer.experiments.projection import IO_SETS
from designer.experiments.settings import PLAIN_64, QUALITY_PRESETS, RenderSettings

SIZE_PX = (960, 640)
N_IMAGES = 8
MIN_CORNERS = 50
CAMERA = IO_SETS[0]  # 1-inch sensor, 8.8 mm: a typical survey drone camera
DISTORTION = BrownConrady(k1=-0.12, k2=0.02)
#: a setting is "as accurate" as another if its std is at most this much larger
STD_TOLERANCE = 1.02
#: a setting is biased if its mean error is significantly (95 %) beyond this (px)
MAX_BIAS_PX = 0.01
OUT_DIR = Path("bench-accuracy")


@dataclass(frozen=True)
class Case:
    """One row: render settings plus the scene/camera variations of the sweep."""

    group: str
    settings: RenderSettings
    texels_per_square: int = 1
    distortion: bool = False
    warp_oversample: int = 1

    @property
    def label(self) -> str:
        text = self.settings.label()
        if self.texels_per_square > 1:
            text += f", {self.texels_per_square} texels/square"
        if self.distortion:
            text += f", distortion warp {self.warp_oversample}x"
        return text


def _s(**kw) -> RenderSettings:
    return RenderSettings(**kw)


def _adaptive(samples: int, minimum: int, threshold: float = 0.01) -> RenderSettings:
    return _s(samples=samples, adaptive_threshold=threshold, adaptive_min_samples=minimum)


CASES: tuple[Case, ...] = (
    *(Case("samples", _s(samples=n)) for n in (1, 4, 16, 32)),
    Case("adaptive", _adaptive(32, 4)),
    Case("adaptive", _adaptive(64, 4)),
    Case("adaptive", _adaptive(128, 4)),
    Case("filter", _s(samples=16, pixel_filter="GAUSSIAN", filter_width_px=1.5)),
    Case("filter", _s(samples=16, pixel_filter="BLACKMAN_HARRIS", filter_width_px=1.5)),
    Case("oversample", _s(samples=4, oversample=2)),
    Case("texture", _s(samples=16), texels_per_square=32),
    Case("texture", _s(samples=16, interpolation="Linear"), texels_per_square=32),
    Case("distortion", _s(samples=16), distortion=True, warp_oversample=1),
    Case("distortion", _s(samples=4), distortion=True, warp_oversample=2),
)
REFERENCE = Case("samples", PLAIN_64)


def _poses(n: int, seed: int = 7) -> list[tuple[np.ndarray, np.ndarray]]:
    """n poses of the camera that each see at least MIN_CORNERS measurable corners (also
    through the distortion, which shrinks the field: poses must work for both)."""
    rng = np.random.default_rng(seed)
    corners = cube_corners()
    cams = [CAMERA.interior(SIZE_PX), replace(CAMERA.interior(SIZE_PX), distortion=DISTORTION)]
    out = []
    while len(out) < n:
        C, R = random_poses(1, rng)[0]
        if all(measurable(corners, C, R, cam, 12, 10)[0].sum() >= MIN_CORNERS for cam in cams):
            out.append((C, R))
    return out


def measure(case: Case, poses, folder: Path, detector: Detector | None = None) -> dict:
    """Render ``poses`` with ``case`` and measure corners: one table row."""
    detector = detector or Detector()
    interior = CAMERA.interior(SIZE_PX)
    if case.distortion:
        interior = replace(interior, distortion=DISTORTION)
    if case.distortion:
        render_interior, warp = pinhole_render_camera(interior, case.warp_oversample)
        views = render_views(folder, [cube_walls(case.texels_per_square)], render_interior,
                             poses, case.settings, bit_depth=16)
        seconds, cpu = list(views.seconds), list(views.cpu_seconds)
        images = []
        for k in range(len(poses)):
            t0, c0 = time.perf_counter(), time.process_time()
            images.append(encode_image(warp.apply(views.linear(k)), np.uint8))
            seconds[k] += time.perf_counter() - t0
            cpu[k] += time.process_time() - c0
    else:
        views = render_views(folder, [cube_walls(case.texels_per_square)], interior, poses,
                             case.settings)
        seconds, cpu = list(views.seconds), list(views.cpu_seconds)
        images = [views.gray(k) for k in range(len(poses))]
    corners = cube_corners()
    errors, n_expected = [], 0
    for k, (C, R) in enumerate(poses):
        ok, uv = measurable(corners, C, R, interior, 12, 10)
        found, det = detector.measure(images[k], uv[ok])
        errors.append(det[found] - uv[ok][found])
        n_expected += int(ok.sum())
    d = np.concatenate(errors)
    mp = SIZE_PX[0] * SIZE_PX[1] / 1e6
    n = len(poses)
    return {
        "group": case.group, "setting": case.label, "settings": case.settings.to_dict(),
        "texels_per_square": case.texels_per_square, "distortion": case.distortion,
        "warp_oversample": case.warp_oversample,
        "s_per_image": float(np.mean(seconds)), "s_per_mp": float(np.sum(seconds) / n / mp),
        "cpu_s_per_mp": float(np.sum(cpu) / n / mp), "corners": len(d),
        "found_fraction": len(d) / max(1, n_expected),
        "mean_dx_px": float(d[:, 0].mean()), "mean_dy_px": float(d[:, 1].mean()),
        "bias_px": float(np.hypot(*d.mean(axis=0))),
        # the larger |mean| of x and y, less its 95 % confidence half-width
        "bias_low_px": float(np.max(np.abs(d.mean(axis=0)) - 1.96 * d.std(axis=0, ddof=1)
                                    / np.sqrt(len(d)))),
        "std_px": float(d.std(ddof=1)),  # pooled over x and y
        "rms_px": float(np.sqrt(np.mean(d * d))),
    }


def run(repeats: int = 1, scale: float = 1.0, out_dir: Path | None = None,
        cases: tuple[Case, ...] = CASES) -> list[dict]:
    """Measure every case (plus plain 64 spp first and last) on the same poses.

    ``repeats`` is not used: every row already renders ``N_IMAGES × scale`` images, and
    one pass of the sweep is what fits in a benchmark's time.
    """
    n = max(2, round(N_IMAGES * scale))
    poses = _poses(n)
    load = [os.getloadavg()[0]]
    rows = []
    with tempfile.TemporaryDirectory(prefix="designer-bench-accuracy-") as tmp:
        first = measure(REFERENCE, poses, Path(tmp) / "ref-first")
        for k, case in enumerate(cases):
            rows.append(measure(case, poses, Path(tmp) / f"case-{k}"))
            load.append(os.getloadavg()[0])
        last = measure(REFERENCE, poses, Path(tmp) / "ref-last")
    ref = dict(first)
    for key in ("s_per_image", "s_per_mp", "cpu_s_per_mp"):
        ref[key] = 0.5 * (first[key] + last[key])
    ref["setting"] += " (reference: mean of first and last run)"
    rows.insert(0, ref)
    _annotate(rows, n, load)
    _write_outputs(rows, Path(out_dir) if out_dir else OUT_DIR)
    return rows


def eligible(row: dict) -> bool:
    """Settings a preset may use: the PSF stays the pixel (a 1 px box filter) and textures
    stay unsmoothed ('Closest') — wider filters and 'Linear' lower the corner spread by
    blurring, which the PSF and texture validations reject — on the plain cube scene."""
    st = row["settings"]
    return (st["pixel_filter"] == "BOX" and st["filter_width_px"] == 1.0
            and st["interpolation"] == "Closest" and row["texels_per_square"] == 1
            and not row["distortion"])


def _annotate(rows: list[dict], n_images: int, load: list[float]) -> None:
    ref = rows[0]
    for r in rows:
        r["x_plain_64"] = r["cpu_s_per_mp"] / ref["cpu_s_per_mp"]
        r["images"] = n_images
        r["load_average"] = [min(load), max(load)]
        r["eligible"] = eligible(r)
    front = [r for r in rows if r["eligible"] and r["bias_low_px"] <= MAX_BIAS_PX]
    for r in rows:
        r["pareto"] = r in front and not any(
            o is not r and o["cpu_s_per_mp"] <= r["cpu_s_per_mp"] and o["std_px"] <= r["std_px"]
            and (o["cpu_s_per_mp"] < r["cpu_s_per_mp"] or o["std_px"] < r["std_px"])
            for o in front)
        r["preset"] = next((name for name, st in QUALITY_PRESETS.items()
                            if st.to_dict() == r["settings"] and r["eligible"]), "")
    for name, target in suggested_presets(rows).items():
        target["suggested"] = name


def suggested_presets(rows: list[dict]) -> dict[str, dict]:
    """For draft, survey and metrology: the cheapest eligible row (by CPU time) whose std is
    at most STD_TOLERANCE × that of plain 4, 16 and 64 spp (the old presets), and whose
    mean error is not significantly beyond MAX_BIAS_PX."""
    plain = {r["settings"]["samples"]: r for r in rows
             if r["eligible"] and r["settings"] == RenderSettings(
                 samples=r["settings"]["samples"]).to_dict()}
    out = {}
    for name, spp in (("draft", 4), ("survey", 16), ("metrology", 64)):
        if spp not in plain:
            continue
        ok = [r for r in rows if r["eligible"] and r["bias_low_px"] <= MAX_BIAS_PX
              and r["std_px"] <= plain[spp]["std_px"] * STD_TOLERANCE]
        if ok:
            out[name] = min(ok, key=lambda r: r["cpu_s_per_mp"])
    return out


def _write_outputs(rows: list[dict], out_dir: Path) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out_dir / "accuracy.json", json.dumps(rows, indent=1) + "\n")
    plot(rows, out_dir / "accuracy-time.png")


def plot(rows: list[dict], path: Path) -> Path:
    """Corner-error std and bias against render time per megapixel, one marker per setting."""
    from designer.experiments.figures import figure, save

    fig = figure(12.5, 5.4)
    ax, bx = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    markers = {"samples": "o", "adaptive": "s", "filter": "^", "oversample": "D",
               "texture": "v", "distortion": "P"}
    for group, marker in markers.items():
        for a, key in ((ax, "std_px"), (bx, "bias_px")):
            g = [r for r in rows if r["group"] == group]
            if not g:
                continue
            filled = [r for r in g if r["eligible"]]
            hollow = [r for r in g if not r["eligible"]]
            colour = f"C{list(markers).index(group)}"
            if filled:
                a.scatter([_t(r) for r in filled], [r[key] for r in filled], marker=marker,
                          s=45, color=colour, label=group)
            if hollow:
                a.scatter([_t(r) for r in hollow], [r[key] for r in hollow], marker=marker,
                          s=45, facecolors="none", edgecolors=colour,
                          label=f"{group} (not eligible)")
    front = sorted((r for r in rows if r["pareto"]), key=_t)
    ax.plot([_t(r) for r in front], [r["std_px"] for r in front], "k--", lw=0.8,
            label="Pareto front (eligible)")
    ref = rows[0]
    ax.axhline(ref["std_px"], color="0.5", ls=":", lw=1)
    ax.axvline(_t(ref) / 4, color="0.5", ls=":", lw=1)
    ax.text(_t(ref) / 4, ax.get_ylim()[1], " ¼ of plain 64 spp's time", fontsize=8,
            va="top", color="0.4")
    for r in rows:
        tag = r.get("suggested") or ("plain 64 spp" if r is ref else "")
        if tag:
            ax.annotate(tag, (_t(r), r["std_px"]), textcoords="offset points",
                        xytext=(-8, -18) if tag == "metrology" else (6, 6), fontsize=9,
                        weight="bold", arrowprops={"arrowstyle": "-", "lw": 0.6})
    for a in (ax, bx):
        a.set_xscale("log")
        a.set_xlabel("render seconds per megapixel, 2 cores (CPU time / 2, log)")
        a.grid(True, which="both", alpha=0.3)
    ax.set_ylabel("corner error std (px)")
    ax.set_title("Spread of the corner error")
    bx.set_ylabel("|mean corner error| (px)")
    bx.set_title("Bias of the corner error")
    ax.legend(fontsize=7, ncol=2)
    return save(fig, path)


def _why_not(row: dict) -> str:
    """Why a row cannot be a preset (see ``eligible``)."""
    st = row["settings"]
    if st["pixel_filter"] != "BOX" or st["filter_width_px"] != 1.0:
        return "blurs: PSF wider than a pixel"
    if st["interpolation"] != "Closest":
        return "blurs the texture"
    if row["distortion"]:
        return "distorted camera"
    return "finer texture (same image)"


def _t(row: dict) -> float:
    return row["cpu_s_per_mp"] / 2


def format_table(rows: list[dict]) -> str:
    head = (f"{'group':<10} {'setting':<50} {'s/MP':>6} {'wall':>6} {'×64':>6} "
            f"{'corners':>7} {'std px':>7} {'bias px':>7} {'mean dx':>8} {'mean dy':>8}  note")
    lines = [head, "-" * len(head)]
    for r in rows:
        note = ", ".join(x for x in (
            "" if r["eligible"] else _why_not(r),
            "Pareto" if r["pareto"] else "",
            f"suggested {r['suggested']}" if r.get("suggested") else "",
            f"preset {r['preset']}" if r["preset"] else "") if x)
        lines.append(
            f"{r['group']:<10} {r['setting'][:50]:<50} {_t(r):>6.2f} {r['s_per_mp']:>6.2f} "
            f"{r['x_plain_64']:>6.3f} {r['corners']:>7} {r['std_px']:>7.4f} "
            f"{r['bias_px']:>7.4f} {r['mean_dx_px']:>+8.4f} {r['mean_dy_px']:>+8.4f}  {note}")
    r0 = rows[0]
    lines.append(
        f"{r0['images']} images of {SIZE_PX[0]}x{SIZE_PX[1]} px ({CAMERA.name}), the same poses "
        f"in every row. s/MP: render seconds per output megapixel on 2 cores, from the CPU time "
        f"of Cycles' render calls / 2 (machine load barely changes it); wall: measured wall "
        f"seconds per MP (load average {r0['load_average'][0]:.1f}-{r0['load_average'][1]:.1f}); "
        f"×64: CPU time relative to plain 64 spp; std pooled over x and y, bias = |mean|. "
        f"Plot and JSON in {OUT_DIR}/")
    return "\n".join(lines)
