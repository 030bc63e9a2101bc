"""How every stage's cost grows with the block (``designer bench scale``).

The example survey (``designer new --template survey``: its camera, 50 m height, 80 / 70 %
overlaps, texture and hills) over square flight areas that give about 60, 240 and 720
images (``--sizes``), the declared terrain 15 m wider than the area on every side as in
the example; the 60-image block is the example itself. Its GCPs: the example's 10 on the
60-image block; beyond it, control points on a k × k grid (k = 4 at 350 m, the
survey-block template's 16) and check points between them, so the density per image stays
near the 2–3 per 100 images practitioners use. ``--scale`` multiplies the example's
resolution scale (1: the example's 1368 × 912 px images; 0.5: 684 × 456 px).

Each block goes end to end in the folder ``bench-scale/`` of the current directory (each
size in its own folder; a size whose files are complete is measured again, never
reused), one whole process per step, as a user runs them:

* ``designer plan``; ``designer render`` (its Blender workers included);
* ``designer reconstruct --mode free --dense cpu --feature-cache …``: features,
  matching, mapping (incremental), adjustment, dense (undistortion, stereo pairs, depth
  maps), fusion, rasters — the wall seconds of each stage from its summary.json, its CPU
  seconds (this process, all threads) where the stage measures them;
* ``designer reconstruct --mapper global --dense none`` with the same feature cache: the
  global mapper's row (features and matches come from the cache);
* ``designer compare`` of the dense cloud with the true surface.

Memory: every step's process tree is sampled every 0.25 s (the sum of the resident sets
of the process and its children, from /proc); a stage's peak is the largest sample
taken while it ran (a reconstruction's stages told apart by the lines it prints). Wall
seconds of a whole process (plan, render, compare) include its start-up.

The table gives, per stage and size, wall seconds, CPU seconds and peak memory, then each
stage's growth exponent between the two largest sizes (log of the wall-seconds ratio over
log of the image-count ratio; 1 is linear); then the accuracy of each block (check RMSE
XY and Z in GSD, the dense cloud's median signed distance to the true surface and the
68.3 % quantile of its absolute distance). ``bench-scale/scale.json`` keeps the rows and
``bench-scale/scale.png`` draws wall seconds against images on log-log axes.
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import threading
import time
from dataclasses import replace
from pathlib import Path

from designer.project.templates import block_of_side

OUT_DIR = Path("bench-scale")
#: the block sizes measured by default (images)
SIZES = (60, 240, 720)
#: the example's flight area (m a side) and its images
EXAMPLE_AREA_M = 70.0
EXAMPLE_IMAGES = 60
#: the table's stages, in processing order
STAGES = ("plan", "render", "features", "matching", "mapping", "mapping (global)",
          "adjustment", "dense", "fusion", "rasters", "compare")
#: the reconstruction's printed lines that start a stage (patterns matched at a line's
#: start; "dense: N points" ends the fusion, the rasters follow)
_RECONSTRUCT_MARKS = ((r"features:", "features"), (r"matching:", "matching"),
                      (r"incremental SfM", "mapping"), (r"global SfM", "mapping (global)"),
                      (r"georeferenced", "adjustment"), (r"bundle adjustment", "adjustment"),
                      (r"dense matching", "dense"), (r"dense: fusing", "fusion"),
                      (r"dense: \d+ points", "rasters"))
#: seconds between two memory samples
SAMPLE_S = 0.25


def block_project(images: int, scale: float = 1.0):
    """The example survey over a square area giving about ``images`` images (the example
    itself at 60), its resolution scale times ``scale``."""
    from designer.project.templates import template

    project = template("survey").project
    area_m = EXAMPLE_AREA_M
    if images != EXAMPLE_IMAGES:
        area_m = _area_for(project, images)
        project = block_of_side(project, area_m)
    render = replace(project.render,
                     resolution_scale=project.render.resolution_scale * scale)
    return replace(project, render=render,
                   name=f"Scale bench: {area_m:.0f} m block, about {images} images")


def _area_for(project, images: int) -> float:
    """The flight area's side (whole metres) whose grid gives about ``images`` stations:
    the count grows with the area, so a few corrections of the side by the square root
    of the ratio settle it."""
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_stations

    area = EXAMPLE_AREA_M * math.sqrt(images / EXAMPLE_IMAGES)
    for _ in range(4):
        area = 2 * round(area / 2)  # the terrain's extent a whole number of grid nodes
        scaled = block_of_side(project, area)
        hf = build_heightfield(scaled.scene.terrain, Path("."), scaled.crs)
        n = len(project_stations(scaled, hf)[0])
        if abs(n - images) <= 0.05 * images:
            break
        area *= math.sqrt(images / n)
    return float(2 * round(area / 2))


class _Sampler:
    """The resident memory of a process tree, sampled in a thread; each sample filed
    under the stage set last."""

    def __init__(self, pid: int) -> None:
        self.pid, self.stage = pid, None
        self.peak_mb: dict = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            mb = _tree_rss_mb(self.pid)
            self.peak_mb[self.stage] = max(self.peak_mb.get(self.stage, 0.0), mb)
            self._stop.wait(SAMPLE_S)

    def stop(self) -> dict:
        self._stop.set()
        self._thread.join()
        return self.peak_mb


def _tree_rss_mb(root: int) -> float:
    """MB resident in process ``root`` and its descendants (0 once it has ended)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            children.setdefault(ppid, []).append(int(entry))
    total_kb, todo = 0, [root]
    while todo:
        pid = todo.pop()
        todo += children.get(pid, [])
        try:
            for line in Path(f"/proc/{pid}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total_kb += int(line.split()[1])
        except OSError:
            continue
    return total_kb / 1024


def _run_step(args: list[str], stage: str, marks=(), log=None) -> dict:
    """Run ``designer ARGS`` as a whole process: its wall and CPU seconds (its children
    included), its peak memory per stage (``marks``: patterns of printed lines → the
    stage they start). A failing step raises with its last lines."""
    cmd = [sys.executable, "-m", "designer", *args]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            bufsize=1)
    sampler = _Sampler(proc.pid)
    sampler.stage = stage
    tail: list[str] = []
    for line in proc.stdout:
        tail = (tail + [line.rstrip()])[-20:]
        for pattern, marked in marks:
            if re.match(pattern, line):
                sampler.stage = marked
                break
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    peaks = sampler.stop()
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        from designer.errors import DesignerError

        raise DesignerError(f"designer {' '.join(args)} failed (exit {proc.returncode}): "
                            + " | ".join(tail[-5:]) + "; the blocks measured before it are "
                            "in bench-scale/scale.json")
    if log is not None:
        log(f"{stage}: {wall:.1f} s")
    return {"wall_s": wall, "cpu_s": usage.ru_utime + usage.ru_stime,
            "peak_mb": max(peaks.values(), default=0.0),
            "max_rss_mb": usage.ru_maxrss / 1024, "peaks_mb": peaks}


def measure_block(images: int, folder: Path, scale: float = 1.0, log=None) -> list[dict]:
    """One block end to end in ``folder``: one row per stage (``STAGES``), the last row
    the block's accuracy and sizes."""
    import shutil

    from designer.project.model_to_xml import write_project

    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    project = block_project(images, scale)
    xml = folder / "block.xml"
    write_project(project, xml)
    rows: dict[str, dict] = {}
    plan = _run_step(["plan", str(xml)], "plan", log=log)
    rows["plan"] = plan
    # what the plan estimates before this block renders (the records of smaller blocks
    # rendered before it count, as on a user's machine)
    planned = _plan_figures(project)
    survey, recon = folder / "survey", folder / "reconstruction"
    rows["render"] = _run_step(["render", str(xml), "-o", str(survey), "--progress", "none"],
                               "render", log=log)
    cache = folder / "feature-cache"
    free = _run_step(["reconstruct", str(survey), "-o", str(recon), "--mode", "free",
                      "--dense", "cpu", "--feature-cache", str(cache)], "reconstruct",
                     _RECONSTRUCT_MARKS, log)
    summary = json.loads((recon / "summary.json").read_text())
    wall, cpu = summary["stage_seconds"], summary.get("stage_cpu_seconds", {})
    dense = summary["dense"]
    ds = dense.get("stage_seconds", {})
    fusion_s = ds.get("fusion_s", 0.0)
    for stage, key in (("features", "features_s"), ("matching", "matching_s"),
                       ("mapping", "reconstruction_s"), ("adjustment", "adjustment_s")):
        rows[stage] = {"wall_s": wall[key], "cpu_s": cpu.get(key)}
    rows["dense"] = {"wall_s": wall["dense_s"] - fusion_s,
                     "cpu_s": sum(ds.get(f"{k}_cpu_s", 0.0)
                                  for k in ("undistort", "pairs", "depth_maps"))}
    rows["fusion"] = {"wall_s": fusion_s, "cpu_s": ds.get("fusion_cpu_s")}
    rows["rasters"] = {"wall_s": wall["rasters_s"], "cpu_s": None}
    for stage in ("features", "matching", "mapping", "adjustment", "dense", "fusion",
                  "rasters"):
        rows[stage]["peak_mb"] = free["peaks_mb"].get(stage)
    glob = _run_step(["reconstruct", str(survey), "-o", str(folder / "reconstruction-global"),
                      "--mode", "free", "--mapper", "global", "--dense", "none",
                      "--feature-cache", str(cache)], "reconstruct", _RECONSTRUCT_MARKS, log)
    gsum = json.loads((folder / "reconstruction-global" / "summary.json").read_text())
    rows["mapping (global)"] = {
        "wall_s": gsum["stage_seconds"]["reconstruction_s"],
        "cpu_s": gsum.get("stage_cpu_seconds", {}).get("reconstruction_s"),
        "peak_mb": glob["peaks_mb"].get("mapping (global)")}
    rows["compare"] = _run_step(["compare", str(recon / "dense.ply"), str(xml), "-o",
                                 str(folder / "compare")], "compare", log=log)
    distances = json.loads((folder / "compare" / "summary.json").read_text())["distances"]
    rows["render"]["estimate_s"] = planned["render_estimate_s"]
    out = [{"images": images, "stage": s, **{k: rows[s].get(k) for k in
                                              ("wall_s", "cpu_s", "peak_mb", "estimate_s")}}
           for s in STAGES]
    gsd_m = planned["gsd_m"]
    check = summary.get("check") or {}
    out.append({
        "images": images, "stage": "block", "registered": summary["registered"],
        "rendered": summary["images"],
        "area_m": _area_of(project), "gsd_m": gsd_m, "texture": planned["texture"],
        "resolution_scale": project.render.resolution_scale,
        "check_n": check.get("n"), "check_rmse_xy_gsd": _in_gsd(check.get("rmse_xy_m"), gsd_m),
        "check_rmse_z_gsd": _in_gsd(check.get("rmse_z_m"), gsd_m),
        "global_registered": gsum["registered"],
        "global_check_rmse_z_gsd": _in_gsd((gsum.get("check") or {}).get("rmse_z_m"), gsd_m),
        "dense_points": dense.get("points"),
        "dense_median_gsd": _in_gsd(distances["median"], gsd_m),
        "dense_abs_q68_gsd": _in_gsd(distances["abs_q68_3"], gsd_m),
        "reconstruct_wall_s": free["wall_s"], "reconstruct_cpu_s": free["cpu_s"],
        "reconstruct_peak_mb": free["peak_mb"], "render_max_rss_mb": rows["render"]["max_rss_mb"],
        "load_average": os.getloadavg()[0]})
    return out


def _in_gsd(value_m, gsd_m):
    return None if value_m is None or not gsd_m else value_m / gsd_m


def _area_of(project) -> float:
    xs = [p[0] for p in project.trajectory.flight_plan.area]
    return max(xs) - min(xs)


def _plan_figures(project) -> dict:
    """The block's median GSD, render estimate (s) and texture path, as ``designer plan``
    gives them (its heightfield is the rendered terrain, surroundings included)."""
    from designer.checks.plan_report import plan_project
    from designer.render_time.model import project_texture_path

    planned = plan_project(project, Path("."))
    return {"gsd_m": float(planned.analysis.median_gsd_m()),
            "render_estimate_s": float(planned.analysis.render_time_s),
            "texture": project_texture_path(project, planned.heightfield.extent_m)}


def exponents(rows: list[dict]) -> dict[str, float]:
    """Each stage's growth exponent between the two largest sizes measured:
    log(wall ratio) / log(image ratio), the images each block's plan rendered (a block
    is named by the size it was laid out for; its plan may give a few images less)."""
    blocks = {r["images"]: r.get("rendered") or r["images"] for r in rows
              if r["stage"] == "block"}
    sizes = sorted(blocks)
    if len(sizes) < 2:
        return {}
    a, b = sizes[-2], sizes[-1]
    ratio = blocks[b] / blocks[a]
    wall = {(r["images"], r["stage"]): r["wall_s"] for r in rows if r["stage"] != "block"}
    out = {}
    for stage in STAGES:
        wa, wb = wall.get((a, stage)), wall.get((b, stage))
        if wa and wb and wa > 0 and wb > 0:
            out[stage] = math.log(wb / wa) / math.log(ratio)
    return out


def run(repeats: int = 1, scale: float = 1.0, sizes: tuple[int, ...] = SIZES,
        on_row=None, out_dir: Path | None = None) -> list[dict]:
    """Every block of ``sizes`` end to end (module docstring); ``repeats`` is ignored
    (one run: the largest takes hours)."""
    folder = Path(out_dir or OUT_DIR)
    folder.mkdir(parents=True, exist_ok=True)
    rows: list[dict] = []
    for n in sorted(sizes):
        block = measure_block(n, folder / f"block-{n}", scale,
                              log=lambda msg, n=n: print(f"{n} images: {msg}",
                                                         file=sys.stderr, flush=True))
        rows += block
        if on_row is not None:
            for r in block:
                on_row(r)
        _write_json(folder / "scale.json", rows)
    try:
        write_figure(rows, folder / "scale.png")
    except ImportError:  # matplotlib is optional
        pass
    return rows


def _write_json(path: Path, rows: list[dict]) -> None:
    from designer.atomic import write_text_atomic

    write_text_atomic(path, json.dumps({"rows": rows, "exponents": exponents(rows)},
                                       indent=1))


def write_figure(rows: list[dict], path: Path) -> Path:
    """Wall seconds of each stage against images, log-log, with a slope-1 guide."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.5))
    sizes = sorted({r["images"] for r in rows if r["stage"] == "block"})
    colours = plt.get_cmap("tab20").colors  # one of its own for each of the 11 stages
    for k, stage in enumerate(STAGES):
        pts = [(r["images"], r["wall_s"]) for r in rows
               if r["stage"] == stage and r["wall_s"] and r["wall_s"] > 0]
        if len(pts) >= 2:
            ax.plot(*zip(*pts, strict=True), marker="os^Dv"[k % 5], color=colours[(2 * k) % 20
                                                                    + (k >= 10)],
                    label=stage)
    if sizes:
        ax.plot(sizes, [sizes[0] and s / sizes[0] for s in sizes], "k--", lw=1,
                label="slope 1 (linear), from 1 s")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("images in the block")
    ax.set_ylabel("wall seconds")
    ax.set_title("designer bench scale: each stage's wall seconds against the block's images")
    ax.legend(fontsize=8, ncol=2)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)
    return path


def format_table(rows: list[dict]) -> str:
    sizes = sorted({r["images"] for r in rows if r["stage"] == "block"})
    blocks = {r["images"]: r for r in rows if r["stage"] == "block"}
    cell = {(r["images"], r["stage"]): r for r in rows if r["stage"] != "block"}
    exp = exponents(rows)

    def num(v, fmt):
        return format(v, fmt) if v is not None else "-"

    head = f"{'stage':<17}" + "".join(f"{f'{n} img wall / CPU s, MB':>30}" for n in sizes)
    lines = ["designer bench scale: the example's camera, overlaps and GCP density; "
             f"{os.cpu_count()} cores; one whole process per step", head]
    for stage in STAGES:
        parts = []
        for n in sizes:
            r = cell.get((n, stage), {})
            parts.append(f"{num(r.get('wall_s'), '.1f'):>10} / {num(r.get('cpu_s'), '.1f'):>7},"
                         f" {num(r.get('peak_mb'), '.0f'):>7}")
        e = exp.get(stage)
        lines.append(f"{stage:<17}" + "".join(f"{p:>30}" for p in parts)
                     + (f"   exponent {e:.2f}" if e is not None else ""))
    estimates = [(n, cell.get((n, "render"), {})) for n in sizes]
    lines.append("render estimated by designer plan before it ran: " + ", ".join(
        f"{n} images {r['estimate_s']:.0f} s ({r['estimate_s'] / r['wall_s']:.2f} of the "
        f"measured)" for n, r in estimates if r.get("estimate_s") and r.get("wall_s")))
    if len(sizes) >= 2:
        lines.append(f"exponent: log(wall ratio) / log(image ratio) between the {sizes[-2]} "
                     f"and {sizes[-1]} blocks, by the images their plans rendered "
                     "(1 = linear)")
    lines.append("")
    lines.append(f"{'block':<10}{'area m':>8}{'scale':>7}{'texture':>11}{'GSD cm':>8}"
                 f"{'reg.':>10}{'check n':>8}{'XY GSD':>8}{'Z GSD':>7}{'global reg.':>12}"
                 f"{'dense pts':>11}{'median d GSD':>13}{'|d| 68% GSD':>12}{'load':>6}")
    for n in sizes:
        b = blocks[n]
        rendered = b.get("rendered") or n  # the images its plan rendered
        lines.append(
            f"{n:<10}{b['area_m']:>8.0f}{b['resolution_scale']:>7.3f}{b['texture']:>11}"
            f"{100 * b['gsd_m']:>8.2f}{b['registered']:>5}/{rendered:<4}"
            f"{num(b['check_n'], 'd'):>8}"
            f"{num(b['check_rmse_xy_gsd'], '.2f'):>8}{num(b['check_rmse_z_gsd'], '.2f'):>7}"
            f"{b['global_registered']:>7}/{rendered:<4}{num(b['dense_points'], 'd'):>11}"
            f"{num(b['dense_median_gsd'], '+.2f'):>13}{num(b['dense_abs_q68_gsd'], '.2f'):>12}"
            f"{b['load_average']:>6.1f}")
    lines.append("wall: seconds as a user waits (plan, render, compare: whole processes with "
                 "their start-up); CPU: all threads, the render's Blender workers included; "
                 "MB: peak resident memory of the step's processes while the stage ran "
                 "(sampled every 0.25 s)")
    return "\n".join(lines)
