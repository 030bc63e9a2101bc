"""The typed render job: JSON round trip, defaults in one place, clear errors."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from designer.render.job_spec import (
    AdaptiveSampling,
    CameraSpec,
    EffectsSpec,
    FrameSpec,
    JobError,
    MaterialSpec,
    MeshSpec,
    RenderJob,
    RenderSpec,
)

CAMERA = CameraSpec(lens_mm=8.8, sensor_width_mm=13.2, sensor_fit="HORIZONTAL",
                    shift_x=0.01, shift_y=-0.02, resolution_x_px=64, resolution_y_px=48,
                    pixel_aspect_x=1.0, pixel_aspect_y=1.0)
MATRIX = ((1.0, 0.0, 0.0, 1.5), (0.0, 1.0, 0.0, -2.25), (0.0, 0.0, 1.0, 30.0),
          (0.0, 0.0, 0.0, 1.0))


def job(**changes) -> RenderJob:
    base = RenderJob(
        output_dir="/tmp/out",
        render=RenderSpec(samples=4, adaptive_sampling=AdaptiveSampling(0.02, 4)),
        camera=CAMERA,
        objects=(MeshSpec("terrain", "terrain.npz",
                          (MaterialSpec(texture="t.png", uv_tiles=(5.0, 5.0),
                                        lightmap="l.png", strength=4.0),)),
                 MeshSpec("targets", "targets.npz",
                          (MaterialSpec(color=(0.8, 0.8, 0.8)),
                           MaterialSpec(color=(0.03, 0.03, 0.03))))),
        frames=(FrameSpec(0, "IMG_0000.png", MATRIX, gsd_m=0.02,
                          flight_direction_uv=(0.0, -1.0), distance_m=80.0),
                FrameSpec(1, "IMG_0001.png", MATRIX)),
        width_px=64, height_px=48,
        origin_world=(500000.0, 5400000.0, 100.0),
        effects=EffectsSpec("project.xml", "p4p", 0.5, "warp.npz"),
        designer_version="0.1.0", project="example")
    return replace(base, **changes)


@pytest.mark.parametrize("changes", [{}, {"effects": None}, {"render": RenderSpec(samples=16)}])
def test_json_round_trip_is_exact(changes):
    original = job(**changes)
    back = RenderJob.from_json(original.to_json())
    assert back == original
    assert back.image_names == {0: "IMG_0000.png", 1: "IMG_0001.png"}


def test_written_and_read_back_through_a_file(tmp_path):
    path = job().write(tmp_path / "job.json")
    assert RenderJob.read(path) == job()
    assert not list(tmp_path.glob(".*"))  # no temporary left beside it


def test_defaults_live_in_the_types():
    data = json.loads(job().to_json())
    del data["render"]["seed"], data["render"]["pixel_filter"], data["camera"]["clip_end_m"]
    del data["background_rgb"]
    back = RenderJob.from_json(json.dumps(data))
    assert back.render.seed == 0 and back.render.pixel_filter == "BOX"
    assert back.camera.clip_end_m == 1e5 and back.background_rgb == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(("mutate", "fragment"), [
    (lambda d: d["render"].update(samples=0), "samples = 0"),
    (lambda d: d["render"].update(format="exr"), "image format 'exr'"),
    (lambda d: d["render"].update(stray=1), "unknown RenderSpec fields"),
    (lambda d: d["objects"][0]["materials"][0].update(color=[1, 1, 1]), "exactly one"),
    (lambda d: d.pop("frames"), "not a render job"),
    (lambda d: d["frames"].append(dict(d["frames"][0])), "repeat"),
])
def test_bad_job_files_name_the_file_and_the_problem(mutate, fragment):
    data = json.loads(job().to_json())
    mutate(data)
    with pytest.raises(JobError, match=fragment) as info:
        RenderJob.from_json(json.dumps(data), "OUT/.designer-job/job.json")
    assert str(info.value).startswith("OUT/.designer-job/job.json: ")
