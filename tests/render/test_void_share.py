"""The void share of rendered images: how much of each image sees no object, measured on
Cycles' own render, recorded in the manifest and warned about by ``designer render``."""

from __future__ import annotations

import dataclasses
import json

import cv2
import numpy as np
import pytest

from designer.core.rotation import rotation_from_opk
from designer.project import model as m
from designer.render.void_share import (
    VOID_MAP_FULL_SCALE,
    VoidSummary,
    void_share_of_map,
    void_summary,
    void_warning,
)
from tests.synthetic import small_survey, write_project_file


def test_the_void_share_is_the_mean_of_the_void_map(tmp_path):
    rng = np.random.default_rng(0)
    coverage = np.zeros((30, 40), np.uint16)
    coverage[:, 30:] = VOID_MAP_FULL_SCALE  # a quarter of the image sees nothing
    coverage[:, 29] = rng.integers(0, VOID_MAP_FULL_SCALE + 1, 30)  # partly void pixels
    cv2.imwrite(str(tmp_path / "map.png"), coverage)
    expected = (coverage.astype(float) / VOID_MAP_FULL_SCALE).mean()
    assert void_share_of_map(tmp_path / "map.png") == pytest.approx(expected, abs=1e-12)
    cv2.imwrite(str(tmp_path / "rgb.png"), np.zeros((30, 40, 3), np.uint8))
    with pytest.raises(ValueError, match="not a void map"):
        void_share_of_map(tmp_path / "rgb.png")
    with pytest.raises(FileNotFoundError, match="no void map"):
        void_share_of_map(tmp_path / "missing.png")


def test_the_summary_counts_images_over_the_threshold_and_names_the_worst():
    summary = void_summary({"b.png": 0.3, "a.png": 0.3, "c.png": 0.01, "d.png": None,
                            "e.png": 0.0})
    assert summary == VoidSummary(images_measured=4, images_over_threshold=2,
                                  threshold_share=0.01, worst_image="a.png", worst_share=0.3)
    line = void_warning(summary)
    assert "2 of 4 images" in line and "a.png with 30.0%" in line
    assert line.endswith("declare <surroundings> in the terrain or enlarge the terrain")
    assert "\n" not in line
    assert void_warning(void_summary({"a.png": 0.01, "b.png": 0.0})) is None
    assert void_summary({"a.png": None}) == VoidSummary(0, 0)


def geometric_void_share(eo: m.ExteriorOrientation, camera: m.Camera, extent: m.Extent,
                         ground_z_m: float) -> float:
    """Share of the pixel centres whose ray meets the plane z = ``ground_z_m`` outside
    the terrain ``extent`` (a camera without distortion, principal point centred)."""
    W, H = camera.image_width_px, camera.image_height_px
    f_px = camera.focal_length_mm * W / camera.sensor_width_mm
    u, v = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
    ray_cam = np.stack([(u - W / 2) / f_px, -(v - H / 2) / f_px, -np.ones_like(u)], axis=-1)
    R = rotation_from_opk(*np.radians([eo.omega_deg, eo.phi_deg, eo.kappa_deg]))
    ray = ray_cam @ R.T
    t = (ground_z_m - eo.Z) / ray[..., 2]
    x, y = eo.X + t * ray[..., 0], eo.Y + t * ray[..., 1]
    inside = ((x >= extent.min_X) & (x <= extent.max_X) & (y >= extent.min_Y)
              & (y <= extent.max_Y))
    return 1.0 - float(inside.mean())


@pytest.mark.blender
@pytest.mark.slow
def test_the_manifest_records_the_void_each_image_sees_and_render_warns(tmp_path, capsys):
    from designer.cli.main import main

    # 40 x 40 m terrain (relief +-0.5 m), black background; one photo from 30 m over the
    # centre, one 15 m east, turned, that sees past the east edge
    project = small_survey(n_photos=2, samples=4, size_px=(160, 120), pixel_pitch_mm=0.04)
    centre, east = project.trajectory.exterior_orientations
    centre = dataclasses.replace(centre, X=0.0, Y=0.0, Z=30.0, omega_deg=0.0, phi_deg=0.0,
                                 kappa_deg=0.0)
    east = dataclasses.replace(east, X=15.0, Y=2.0, Z=30.0, omega_deg=3.0, phi_deg=-2.0,
                               kappa_deg=20.0)
    # no surroundings: the east photo sees the black background past the terrain's edge
    terrain = dataclasses.replace(project.scene.terrain, surroundings="none")
    project = dataclasses.replace(project, trajectory=m.Trajectory((centre, east)),
                                  scene=dataclasses.replace(project.scene, terrain=terrain))
    path = write_project_file(project, tmp_path)
    out = tmp_path / "out"
    assert main(["render", str(path), "-o", str(out), "--workers", "1",
                 "--progress", "none"]) == 0
    manifest = json.loads((out / "manifest.json").read_text())
    shares = {name: entry["void_share"] for name, entry in manifest["images"].items()}
    expected = geometric_void_share(east, project.cameras[0],
                                    project.scene.terrain.extent, 0.0)
    assert 0.2 < expected < 0.5
    assert shares[east.name] == pytest.approx(expected, abs=0.02)
    assert shares[centre.name] == 0.0  # over the terrain: no void
    assert manifest["void"] == {"images_measured": 2, "images_over_threshold": 1,
                                "threshold_share": 0.01, "worst_image": east.name,
                                "worst_share": shares[east.name]}
    warning = capsys.readouterr().err.strip().splitlines()[-1]
    assert warning.startswith("designer: warning: 1 of 2 images") and east.name in warning
    assert f"{shares[east.name]:.1%}" in warning
    assert "declare <surroundings> in the terrain or enlarge the terrain" in warning


@pytest.mark.blender
@pytest.mark.slow
def test_an_object_as_black_as_the_background_is_not_void(tmp_path):
    from designer.render.job_spec import (
        CameraSpec,
        FrameSpec,
        MaterialSpec,
        MeshSpec,
        RenderJob,
        RenderSpec,
    )
    from designer.render.runner import render_frames

    # a black 10 x 10 m square on the black background, seen from 10 m above x = 5 m:
    # its east edge runs down the middle of the image (a 12.8 m wide footprint)
    job_dir = tmp_path / "job"
    job_dir.mkdir()
    np.savez(job_dir / "square.npz",
             vertices_local=np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], float),
             faces=np.array([[0, 1, 2], [0, 2, 3]], np.int64))
    pose = ((1.0, 0.0, 0.0, 5.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 10.0),
            (0.0, 0.0, 0.0, 1.0))
    job = RenderJob(
        output_dir=str(tmp_path / "images"), render=RenderSpec(samples=4),
        camera=CameraSpec(lens_mm=5.0, sensor_width_mm=6.4, sensor_fit="HORIZONTAL",
                          shift_x=0.0, shift_y=0.0, resolution_x_px=160,
                          resolution_y_px=120, pixel_aspect_x=1.0, pixel_aspect_y=1.0),
        objects=(MeshSpec("square", "square.npz", (MaterialSpec(color=(0.0, 0.0, 0.0)),)),),
        frames=(FrameSpec(index=0, image_name="black.png", matrix_world_local=pose),),
        width_px=160, height_px=120)
    events = []
    report = render_frames(job.write(job_dir / "job.json"), [0], workers=1,
                           progress=events.append)
    image = cv2.imread(str(tmp_path / "images" / "black.png"))
    assert not image.any()  # every pixel the background's colour
    assert report.void_share == {0: pytest.approx(0.5, abs=0.01)}
    done = next(e for e in events if e["event"] == "frame_done")
    assert done["void_share"] == report.void_share[0] and "void_s" in done["stages"]
