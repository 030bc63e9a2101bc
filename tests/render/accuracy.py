"""Real Cycles renders: detected GCP target centres against the exported pixel
coordinates — the cases and the checks, shared by the two test files that render them
(test_render_accuracy.py: the pinhole and Brown–Conrady lenses; test_render_accuracy_fisheye
.py: the 148° fisheye, as costly as the others together, so the two run side by side)."""

from __future__ import annotations

import json
from dataclasses import replace

import cv2
import numpy as np
import pycolmap

from designer.export.tables import read_gcp_observations_csv, read_gcp_truth_csv
from designer.project import model as m
from designer.render.pipeline import render_project
from tests.render.helpers import detect_centres
from tests.synthetic import small_survey, write_project_file

CASES = {
    # the plain pinhole with a UTM-sized origin, a principal point offset and a lens and
    # sensor below Blender's 1 mm minimum (both are scaled, not clamped) in one render
    # (the distorted cases below are at the local origin)
    "UTM-sized origin, sub-millimetre sensor": dict(
        origin=(500000.0, 5000000.0, 250.0), principal_point_mm=(0.031, -0.017),
        focal_length_mm=0.5, pixel_pitch_mm=0.001),
    # Distorted cameras: rendered as an enlarged pinhole and warped (designer.effects).
    # Radial barrel and tangential terms with a principal point offset in one render
    "barrel and tangential": dict(
        focal_length_mm=8.0, principal_point_mm=(0.2, 0.1),
        distortion=m.BrownConradyDistortion(k1=-0.3, k2=0.05, p1=0.002, p2=-0.0015)),
    "pincushion k1=+0.2": dict(focal_length_mm=8.0,
                               distortion=m.BrownConradyDistortion(k1=0.2)),
    "fisheye 148 deg": dict(focal_length_mm=3.1,
                            distortion=m.FisheyeEquidistantDistortion(k1=0.01)),
}
#: cornerSubPix half-window (px): the fisheye's targets are 10-15 px wide, and an 11 x 11
#: window would reach past them into the grass.
HALF_WINDOW = {"fisheye 148 deg": 3}
#: photos per case where not N_PHOTOS. A case costs its photos (a 640 x 480 frame of 16
#: samples ~3.5 s of CPU; a 148° fisheye frame, rendered as a pinhole of ~6 times the
#: pixels by designer.effects.distortion_render, ~20 s), so each photo sees as many
#: targets as fit (TARGET_GRID_M): 97-112 centres in the Brown cases' 6 photos, 147 in the
#: wide pinhole's 4, 98 in the fisheye's 2 (the mean's standard error < 0.01 px)
PHOTOS = {"UTM-sized origin, sub-millimetre sensor": 4, "fisheye 148 deg": 2}
N_PHOTOS = 6
#: the targets' east and north offsets from the origin (m): a 7 x 7 grid 5 m apart over
#: the 40 m terrain (small_survey's 9 targets 10 m apart among them), 1.5 m checkers
TARGET_GRID_M = tuple(-15.0 + 5.0 * k for k in range(7))


def accuracy_survey(name: str) -> m.Project:
    """small_survey with case ``name``'s camera and TARGET_GRID_M's 49 targets, all
    surveyed exactly at their true position (the origin's height)."""
    project = small_survey(n_photos=PHOTOS.get(name, N_PHOTOS), **CASES[name])
    E0, N0, H0 = project.origin.E0, project.origin.N0, project.origin.H0
    targets = tuple(
        m.Target(f"T{a}{b}", "check" if (a + b) % 2 else "control", "checker", 1.5,
                 m.TruePosition(E0 + x, N0 + y),
                 m.SurveyedPosition(m.Point3(E0 + x, N0 + y, H0), m.Sigma3(0.0, 0.0, 0.0)))
        for a, x in enumerate(TARGET_GRID_M) for b, y in enumerate(TARGET_GRID_M))
    return replace(project, scene=replace(project.scene, targets=replace(
        project.scene.targets, targets=targets)))


def render_case(name: str, tmp_path_factory):
    """(name, the render's summary) of case ``name``."""
    folder = tmp_path_factory.mktemp(name.replace(" ", "-"))
    project_path = write_project_file(accuracy_survey(name), folder)
    return name, render_project(project_path, folder / "out", workers=1)


def check_target_centres(rendered) -> None:
    """Detected target centres lie on the exported pixel coordinates: |mean| ≤ 0.02 px,
    RMS ≤ 0.1 px, over at least 12 centres (every case: with 9 targets 10 m apart the
    strong pincushion needed 0.035 px, its corner detector's bias on curved checker edges
    coming to 0.030 px over 66 centres; over TARGET_GRID_M's it is under 0.01 px)."""
    name, summary = rendered
    obs = read_gcp_observations_csv(summary.ground_truth["gcp_observations"])
    rng = np.random.default_rng(0)
    errors = []
    for image_name in sorted({o.image_name for o in obs}):
        rows = [o for o in obs if o.image_name == image_name]
        uv = np.array([o.uv_px for o in rows])
        W, H = summary.prepared.interior.image_size_px
        keep = (uv[:, 0] > 12) & (uv[:, 0] < W - 12) & (uv[:, 1] > 12) & (uv[:, 1] < H - 12)
        gray = cv2.imread(str(summary.images_dir / image_name), cv2.IMREAD_GRAYSCALE)
        errors.append(detect_centres(gray, uv[keep], rng, HALF_WINDOW.get(name, 5)) - uv[keep])
    d = np.concatenate(errors)
    assert len(d) >= 12, f"{name}: only {len(d)} targets seen"
    mean, rms = d.mean(axis=0), np.sqrt((d ** 2).mean(axis=0))
    print(f"{name}: {len(d)} target centres, mean {mean} px, RMS {rms} px")
    assert np.all(np.abs(mean) <= 0.02), f"{name}: mean error {mean} px"
    assert np.all(rms <= 0.1), f"{name}: RMS error {rms} px"


def check_pycolmap_projects_like_the_odm_gcp_list(rendered) -> None:
    """pycolmap's projection of the true GCPs through the exported model is gcp_list.txt's
    pixel (ODM's origin: the centre of the top-left pixel)."""
    _, summary = rendered
    from designer.export.colmap_read import model_offset_world

    rec = pycolmap.Reconstruction(str(summary.ground_truth["colmap"]))
    # the model is local: world − the offset written beside it
    offset = model_offset_world(summary.ground_truth["colmap"])
    truth = {g.gcp_id: g.true_xyz - offset
             for g in read_gcp_truth_csv(summary.ground_truth["gcp_truth"])}
    lines = summary.ground_truth["odm_gcp_list"].read_text().splitlines()[1:]
    assert lines
    for line in lines:
        # gcp_list.txt carries the surveyed coordinates; the pixels are those of the truth.
        _, _, _, u, v, image_name, gcp_id = line.split()[:7]
        image = rec.find_image_with_name(image_name)
        uv = image.project_point(truth[gcp_id])
        # ODM's pixel origin is the centre of the top-left pixel: 0.5 px from COLMAP's.
        assert np.allclose(uv, [float(u) + 0.5, float(v) + 0.5], atol=1e-6)


def check_manifest_and_images(rendered) -> None:
    """The manifest lists every image, each with its render time; the images folder holds
    exactly those images and nothing partial stays anywhere."""
    name, summary = rendered
    manifest = json.loads(summary.manifest.read_text())
    assert manifest["blender_version"]
    assert len(manifest["images"]) == manifest["frames_total"] == PHOTOS.get(name, N_PHOTOS)
    assert all(v["render_seconds"] > 0 for v in manifest["images"].values())
    assert sorted(p.name for p in summary.images_dir.iterdir()) == sorted(manifest["images"])
    assert list((summary.out_dir / ".designer-job" / "partial").iterdir()) == []
