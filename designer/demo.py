"""The example survey, end to end: every stage, in order, with timings.

Stages: write the example project → check it → plan it (maps) → render every image
(with the terrain's surroundings, so no image sees past the terrain) with its camera
effects and ground truth → reconstruct with COLMAP (incremental SfM with the camera's
true calibration held fixed, then a similarity onto the control GCPs, marked exactly
where their centres project: the ideal case of the SfM-accuracy literature, not a survey
workflow with self-calibration and marking error) and the CPU dense matcher (dense
cloud, DSM, DEM of difference) → compare the dense cloud with the true mesh over the area
of interest and the check points with their truth → report (Markdown with figures, GCP
table, calibration, timings).
The accuracy targets, in ground sample distances (GSD): cloud vs mesh median |d| ≤ 1,
check-point RMSE ≤ 1 horizontally and ≤ 1.5 vertically.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from pathlib import Path

from designer.atomic import write_text_atomic
from designer.core.layout import (
    GROUND_TRUTH_DIR,
    IMAGES_DIR,
    SIDE_BY_SIDE_ACCURACY_DIR,
    SIDE_BY_SIDE_RECONSTRUCTION_DIR,
    SIDE_BY_SIDE_SURVEY_DIR,
)

#: the render output folder inside the demo's folder (its images in SURVEY_DIR/images/);
#: the reconstruction and the comparison beside it, where the window finds them
SURVEY_DIR = SIDE_BY_SIDE_SURVEY_DIR
RECONSTRUCTION_DIR = SIDE_BY_SIDE_RECONSTRUCTION_DIR
ACCURACY_DIR = SIDE_BY_SIDE_ACCURACY_DIR
#: the longer image side the demo's dense matching uses: 912 px of 1368 halves the
#: matching time for 1.6 cm instead of 1.0 cm median |d| (designer bench dense)
DEMO_DENSE_MAX_IMAGE_PX = 912


def run_demo(
    output: Path,
    log: Callable[[str], None] = print,
    quality: str | None = None,
    frames: str | None = None,
) -> Path:
    """Run the demo into ``output``; returns the path of the report."""
    from designer.checks.plan_report import format_plan, plan_project, plan_summary
    from designer.project import load_project
    from designer.render.pipeline import render_project
    from designer.survey.maps import write_coverage_map, write_gsd_map

    # COLMAP's per-step INFO lines (dense fusion prints one per image) stay out of the
    # demo's output; warnings and errors still show (read when pycolmap loads)
    os.environ.setdefault("GLOG_minloglevel", "1")
    output = Path(output)
    output.mkdir(parents=True, exist_ok=True)
    timings: dict[str, float] = {}

    def stage(name: str):
        log(f"== {name}")
        return _Timer(timings, name)

    with stage("write the example project"):
        project_path = write_demo_project(output)
    with stage("check"):
        project = load_project(project_path)
        log(f"{project_path}: valid")
    with stage("plan"):
        plan = plan_project(project, output)
        log(format_plan(plan, str(project_path)))
        import numpy as np

        area = np.array(project.trajectory.flight_plan.area)
        xy = np.array([s.C_world[:2] for s in plan.stations])
        write_coverage_map(output / "plan-coverage.png", plan.analysis.coverage, area=area,
                           stations_xy=xy)
        write_gsd_map(output / "plan-gsd.png", plan.analysis.coverage, area=area,
                      stations_xy=xy)
    with stage("render"):
        summary = render_project(project_path, output / project.outputs.directory,
                                 quality=quality, frames=frames, resume=True,
                                 progress=_frame_logger(log, len(plan.stations)))
        log(f"{len(summary.report.rendered)} images rendered, "
            f"{len(summary.report.skipped)} already complete")
    accuracy = None
    if frames is None:
        with stage("reconstruct (COLMAP)"):
            from designer.sfm.reconstruct import reconstruct

            # the project's processing (the defaults: true calibration held fixed, a
            # similarity onto exactly marked control GCPs) and the dense cloud; 4096 SIFT
            # features per 1.2 MP image, found on the image at its own size (demo_processing)
            recon = reconstruct(output / SURVEY_DIR, output / RECONSTRUCTION_DIR, mode="free",
                                log=log, processing=demo_processing(project),
                                project_path=project_path,
                                dense_max_image_px=DEMO_DENSE_MAX_IMAGE_PX)
        with stage("compare with the truth"):
            accuracy = _compare(project_path, recon, plan, output / ACCURACY_DIR, log)
    report = output / "report.md"
    text = _report_text(project, plan_summary(plan), summary, timings, accuracy)
    if accuracy is not None:
        text += _processing_text(recon.summary)
    write_text_atomic(report, text)
    write_text_atomic(output / "timings.json", json.dumps(timings, indent=1))
    for name, seconds in timings.items():
        log(f"{name:<28} {seconds:8.1f} s")
    return report


def demo_processing(project):
    """The processing the demo reconstructs with: the project's (the defaults: true
    calibration held fixed, a similarity onto exactly marked control GCPs) with the dense
    cloud, and 4096 SIFT features per 1.2 MP image (plenty, and half the matching time),
    found on the image at its own size rather than doubled: a quarter of the extraction
    work, and the same accuracy (on the demo's images: features 15 s instead of 56 s,
    median |d| 0.28 instead of 0.30 GSD, check RMSE XY 0.13 and Z 0.23 GSD both ways)."""
    from dataclasses import replace

    from designer.project import model as m

    processing = project.processing or m.Processing()
    return replace(processing, dense="cpu",
                   matching=replace(processing.matching, max_features=4096,
                                    sift_scale="original"))


def write_demo_project(output: Path) -> Path:
    """Write the demo's project, the example survey, as ``output``/survey.xml; returns
    its path. Its output folder is the one the demo renders into (SURVEY_DIR), so the
    window opening it finds the demo's images, ground truth and render records; its
    processing is the demo's (:func:`demo_processing`)."""
    from dataclasses import replace

    from designer.project import template, write_project

    project = template("survey").project
    project = replace(project, outputs=replace(project.outputs, directory=SURVEY_DIR))
    # the processing it reconstructs with, so the window does not find its reconstruction
    # made with other settings
    project = replace(project, processing=demo_processing(project))
    project_path = Path(output) / "survey.xml"
    project_path.parent.mkdir(parents=True, exist_ok=True)
    write_project(project, project_path)
    return project_path


class _Timer:
    def __init__(self, timings: dict[str, float], name: str) -> None:
        self.timings, self.name = timings, name

    def __enter__(self):
        self.t0 = time.perf_counter()
        return self

    def __exit__(self, *exc) -> None:
        self.timings[self.name] = time.perf_counter() - self.t0


def _frame_logger(log, total: int):
    done = [0]

    def progress(event: dict) -> None:
        if event["event"] in ("frame_done", "frame_skipped"):
            done[0] += 1
            if done[0] % 10 == 0 or done[0] == total:
                log(f"  {done[0]}/{total} images")

    return progress


def _compare(project_path: Path, recon, plan, out: Path, log) -> dict:
    """Cloud vs mesh and check points vs truth, in metres and in GSD."""
    import numpy as np

    from designer.evaluate.compare import compare_cloud, crop_to_area, reference_mesh
    from designer.evaluate.gcp import gcp_errors
    from designer.evaluate.point_clouds import read_point_cloud
    from designer.export.tables import read_gcp_truth_csv
    from designer.project import load_project
    from designer.survey.surroundings import project_surroundings

    truth = read_gcp_truth_csv(recon.out_dir.parent / SURVEY_DIR / GROUND_TRUTH_DIR /
                               "gcp_truth.csv")
    estimated = {r["id"]: r["estimated"] for r in recon.summary["gcps"]}
    gcps = gcp_errors(estimated, truth)
    dense_ply = recon.out_dir / "dense.ply"
    cloud = read_point_cloud(dense_ply if dense_ply.is_file() else recon.cloud_ply)
    # The truth covers the surroundings the images saw; the statistics cover the area of
    # interest (the declared terrain extent), as designer compare's default.
    project = load_project(project_path)
    growth = project_surroundings(project, project_path.parent)[0]
    truth = reference_mesh(project_path, growth=growth)
    n_all = len(cloud)
    cloud, area = crop_to_area(cloud, truth, "aoi")
    log(f"{len(cloud)} of {n_all} cloud points lie over the area of interest")
    summary = compare_cloud(cloud, truth, out, gcps=gcps, area=area)
    from plyfile import PlyData

    from designer.evaluate.writers import SCALAR_NAME

    d = PlyData.read(str(out / summary["files"]["distances"]))["vertex"][SCALAR_NAME]
    gsd = plan.analysis.median_gsd_m()
    stats = dict(summary["distances"], abs_median=float(np.nanmedian(np.abs(d))))
    check = gcps["summary"]["check"]
    result = {
        "gsd_m": gsd, "points": stats["n"], "points_outside_terrain": area["points_left_out"],
        "median_abs_d_m": stats["abs_median"],
        "median_abs_d_gsd": stats["abs_median"] / gsd,
        "check_rmse_xy_gsd": check["rmse_XY"] / gsd,
        "check_rmse_z_gsd": check["rmse_Z"] / gsd,
    }
    result["pass"] = bool(result["median_abs_d_gsd"] <= 1.0 and result["check_rmse_xy_gsd"]
                          <= 1.0 and result["check_rmse_z_gsd"] <= 1.5)
    log(f"cloud vs mesh: median |d| {100 * stats['abs_median']:.2f} cm = "
        f"{result['median_abs_d_gsd']:.2f} GSD (target <= 1) over {stats['n']} points")
    log(f"check points: RMSE XY {100 * check['rmse_XY']:.2f} cm = "
        f"{result['check_rmse_xy_gsd']:.2f} GSD (<= 1), Z {100 * check['rmse_Z']:.2f} cm = "
        f"{result['check_rmse_z_gsd']:.2f} GSD (<= 1.5): "
        f"{'PASS' if result['pass'] else 'FAIL'}")
    write_text_atomic(out / "demo_accuracy.json", json.dumps(result, indent=1))
    return result


def _report_text(project, plan: dict, summary, timings: dict[str, float],
                 accuracy: dict | None = None) -> str:
    first = summary.prepared.poses[len(summary.prepared.poses) // 2].image_name
    lines = [
        f"# {project.name}",
        "",
        project.description or "",
        "",
        "## Plan",
        "",
        f"* images: {plan['n_images']}",
        f"* GSD over the terrain (min / mean / max): "
        f"{100 * plan['gsd_terrain_m']['min']:.2f} / {100 * plan['gsd_terrain_m']['mean']:.2f}"
        f" / {100 * plan['gsd_terrain_m']['max']:.2f} cm",
        f"* front / side overlap (median): {100 * plan['front_overlap_median']:.1f} % / "
        f"{100 * plan['side_overlap_median']:.1f} %",
        "",
        "![coverage](plan-coverage.png) ![GSD](plan-gsd.png)",
        "",
        "## A rendered image",
        "",
        f"![{first}]({SURVEY_DIR}/{IMAGES_DIR}/{first})",
        "",
        "## GCPs (images that see each target unoccluded)",
        "",
        "| GCP | role | images |",
        "|---|---|---|",
    ]
    lines += [f"| {g['id']} | {g['role']} | {g['images']} |" for g in plan.get("gcps", [])]
    if accuracy is not None:
        gsd_cm = 100 * accuracy["gsd_m"]
        lines += [
            "", "## Accuracy of the COLMAP reconstruction", "",
            f"GSD {gsd_cm:.2f} cm. Targets: median |d| <= 1 GSD; check-point RMSE <= 1 GSD "
            "horizontally, <= 1.5 GSD vertically.", "",
            "Processing: incremental SfM with the camera's true calibration held fixed, "
            "then a similarity transform onto the control GCPs, marked exactly where their "
            "centres project — the ideal case of the SfM-accuracy literature (no "
            "self-calibration, no marking error). Distances are over the area of interest "
            f"(the declared terrain, {accuracy['points_outside_terrain']} points outside it "
            "left out).", "",
            "| figure | value | in GSD |", "|---|---|---|",
            f"| dense cloud vs true mesh, median abs. distance ({accuracy['points']} points)"
            f" | {100 * accuracy['median_abs_d_m']:.2f} cm | {accuracy['median_abs_d_gsd']:.2f} |",
            f"| check points, RMSE XY | {gsd_cm * accuracy['check_rmse_xy_gsd']:.2f} cm | "
            f"{accuracy['check_rmse_xy_gsd']:.2f} |",
            f"| check points, RMSE Z | {gsd_cm * accuracy['check_rmse_z_gsd']:.2f} cm | "
            f"{accuracy['check_rmse_z_gsd']:.2f} |", "",
            f"Result: **{'PASS' if accuracy['pass'] else 'FAIL'}**", "",
            "![error map](accuracy/error_map.png) ![histogram](accuracy/histogram.png)", "",
            "Details: `accuracy/report.html`, `accuracy/summary.json`, "
            "`reconstruction/gcp_residuals.csv`."]
    lines += ["", "## Timings", "", "| stage | seconds |", "|---|---|"]
    lines += [f"| {name} | {seconds:.1f} |" for name, seconds in timings.items()]
    lines += ["", f"Images: `{SURVEY_DIR}/{IMAGES_DIR}/`; ground truth: "
              f"`{SURVEY_DIR}/{GROUND_TRUTH_DIR}/`; manifest: `{SURVEY_DIR}/manifest.json`; "
              f"which file each program takes: `{SURVEY_DIR}/README.txt`.", ""]
    return "\n".join(lines)


def _processing_text(summary: dict) -> str:
    """The reconstruction's side of the report: DoD, GCP table, calibration, stage times."""
    lines = ["", "## Processing", ""]
    dense = summary.get("dense") or {}
    if dense.get("status") == "ok":
        dome = dense.get("dome_amplitude_m")
        dod = dense["rasters"]["dod"]
        lines += [
            f"Dense cloud: {dense['points']} points ({dense['matcher']}, longer image side "
            f"{dense.get('max_image_size_px') or 'full'} px). DEM of difference (DSM − true "
            f"surface, {100 * dense['dsm_cell_m']:.1f} cm cells): median "
            f"{100 * dod['median_m']:+.2f} cm, NMAD {100 * dod['nmad_m']:.2f} cm; fitted "
            + (f"{dense.get('dome_kind', 'dome')} amplitude {100 * dome:+.2f} cm "
               f"({dense['dome_amplitude_gsd']:+.2f} GSD)." if dome is not None
               else "surface: no dome."), "",
            "![DoD](reconstruction/dod.png) ![profile](reconstruction/dod_profile.png)", ""]
    lines += ["| GCP | role | images | dX cm | dY cm | dZ cm | image RMSE px |",
              "|---|---|---|---|---|---|---|"]
    for r in summary.get("gcps", []):
        d = [100 * r[k] for k in ("dx_m", "dy_m", "dz_m")]
        px = r.get("image_residuals_px") or []
        rms = sum(du * du + dv * dv for du, dv in px) / len(px) if px else float("nan")
        rms = rms ** 0.5
        lines.append(f"| {r['id']} | {r['role']} | {r['images']} | {d[0]:+.2f} | "
                     f"{d[1]:+.2f} | {d[2]:+.2f} | {rms:.2f} |")
    intr = summary.get("intrinsics") or {}
    if intr:
        lines += ["", "Calibration, estimated − true: "
                  f"Δf {intr['delta_f_px']:+.2f} px, Δcx {intr['delta_cx_px']:+.2f} px, "
                  f"Δcy {intr['delta_cy_px']:+.2f} px, Δk1 {intr['delta_k1']:+.2e}; radial "
                  f"distortion difference at most {intr['radial_difference_px']['max_abs_px']:.2f}"
                  " px over the image."]
    lines += ["", "| reconstruction stage | seconds |", "|---|---|"]
    lines += [f"| {k.removesuffix('_s')} | {v:.1f} |"
              for k, v in (summary.get("stage_seconds") or {}).items()]
    return "\n".join(lines) + "\n"
