"""The typed render job: JSON round trip of every part, defaults in one place, clear
errors (an unknown field anywhere is named with its place)."""

from __future__ import annotations

import dataclasses
import json
from dataclasses import replace

import pytest

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.project import model as m
from designer.render.job_spec import (
    TEXTURE_UV_MAP,
    AdaptiveSampling,
    CameraEffectsSpec,
    CameraSpec,
    EffectsSpec,
    FrameSpec,
    JobError,
    LightStep,
    MaterialSpec,
    MeshSpec,
    PlantSetSpec,
    RenderJob,
    RenderSpec,
    TiledTextureSpec,
    WindSpec,
    job_dataclasses,
)

CAMERA = CameraSpec(lens_mm=8.8, sensor_width_mm=13.2, sensor_fit="HORIZONTAL",
                    shift_x=0.01, shift_y=-0.02, resolution_x_px=64, resolution_y_px=48,
                    pixel_aspect_x=1.0, pixel_aspect_y=1.0)
MATRIX = ((1.0, 0.0, 0.0, 1.5), (0.0, 1.0, 0.0, -2.25), (0.0, 0.0, 1.0, 30.0),
          (0.0, 0.0, 0.0, 1.0))
MATRIX_LATER = ((1.0, 0.0, 0.0, 1.75), (0.0, 1.0, 0.0, -2.25), (0.0, 0.0, 1.0, 30.0),
                (0.0, 0.0, 0.0, 1.0))
INTERIOR = InteriorOrientation(8.8, 13.2, 9.9, 64, 48, distortion=BrownConrady(k1=-0.05))


def job(**changes) -> RenderJob:
    """A small single-camera job (the tests below change parts of it)."""
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
        effects=EffectsSpec(model=m.Effects(blur=m.Blur(0.5)),
                            cameras={"p4p": CameraEffectsSpec(INTERIOR, "warp.npz")}),
        designer_version="0.1.0", project="example")
    return replace(base, **changes)


def full_job() -> RenderJob:
    """A job using every part, each field of each part away from its default somewhere:
    a two-camera rig (Brown–Conrady and fisheye lenses) with every camera effect, a sun
    over time (light steps), moving objects, plants in the wind, a rolling shutter."""
    lit = MaterialSpec(texture="texture_varied.png", uv_tiles=(4.0, 3.0),
                       interpolation="Linear", lightmap="lightmap.png", strength=2.5,
                       uv_map=TEXTURE_UV_MAP, extension="EXTEND", variation="variation.png",
                       variation_warp="variation_warp.png", variation_warp_uv=0.125,
                       texture_colorspace="Non-Color")
    grey = MaterialSpec(color=(0.25, 0.5, 0.75))
    side = CameraSpec(lens_mm=4.5, sensor_width_mm=6.4, sensor_fit="VERTICAL", shift_x=-0.03,
                      shift_y=0.04, resolution_x_px=40, resolution_y_px=30,
                      pixel_aspect_x=1.0, pixel_aspect_y=1.125, clip_start_m=0.5,
                      clip_end_m=900.0)
    # 64 × 48 px over 13.2 × 8.8 mm: pixels 0.889 times as high as wide
    aspect = (8.8 / 48) / (13.2 / 64)
    nadir = InteriorOrientation(8.8, 13.2, 8.8, 64, 48, principal_point_x_mm=0.03,
                                principal_point_y_mm=-0.02, pixel_aspect=aspect,
                                distortion=BrownConrady(k1=-0.05, k2=0.01, k3=-0.001,
                                                        p1=0.0005, p2=-0.0003))
    fisheye = InteriorOrientation(2.5, 6.4, 4.8, 40, 30,
                                  distortion=FisheyeEquidistant(k1=0.01, k2=-0.002,
                                                                k3=0.0003, k4=-0.00004))
    effects = m.Effects(
        vignetting=m.Vignetting(corner_falloff=0.2, rho4=0.05, rho6=-0.01, natural_cos4=True),
        sensor_noise=m.SensorNoise(sigma_dn=1.5, seed=3),
        sensor=m.Sensor(full_well_e=20000.0, read_noise_e=3.0, dark_current_e_per_s=5.0,
                        exposure_time_s=0.002, adc_bits=10, exposure_scale=0.7, seed=4),
        blur=m.Blur(0.7), motion_blur=m.MotionBlur(0.001, 12.0), jpeg=m.Jpeg(90),
        defocus=m.Defocus(2.8, 25.0, object_distance_m=30.0),
        exposure_variation=m.ExposureVariation(exposure_sigma_ev=0.2,
                                               white_balance_sigma_k=300.0,
                                               reference_k=6000.0, seed=5),
        chromatic_aberration=m.ChromaticAberration(red_scale_ppm=120.0, blue_scale_ppm=-80.0))
    step = LightStep(sun_azimuth_deg=135.5, sun_elevation_deg=42.25,
                     objects=(MeshSpec("terrain", "terrain.npz", (lit,)),))
    timed = {"time_s": 12.5, "time_utc": "2026-06-21T09:30:12.500000Z",
             "sun_azimuth_deg": 135.5, "sun_elevation_deg": 42.25, "light_step": 0}
    return RenderJob(
        output_dir="/data/survey/images",
        render=RenderSpec(samples=64, seed=7, pixel_filter="GAUSSIAN", filter_width_px=1.5,
                          format="tiff", bit_depth=16, quality="metrology",
                          adaptive_sampling=AdaptiveSampling(threshold=0.02, min_samples=4),
                          threads=2),
        camera=replace(CAMERA, clip_start_m=0.25, clip_end_m=2000.0),
        objects=(MeshSpec("terrain", "terrain.npz", (lit,)),
                 MeshSpec("gcp_targets", "targets.npz", (grey, grey))),
        frames=(
            FrameSpec(0, "nadir_0000.tif", MATRIX, gsd_m=0.02, flight_direction_uv=(0.0, -1.0),
                      distance_m=80.0, **timed,
                      moving_poses=(("car", 10.0, -4.0, 0.5, 270.0),),
                      shutter_matrices_local=(MATRIX, MATRIX_LATER),
                      camera=CAMERA, camera_id="nadir", size_px=(64, 48),
                      texture_tiles=(3, 4, 8)),
            FrameSpec(1, "side_0000.tif", MATRIX_LATER, gsd_m=0.03,
                      flight_direction_uv=(1.0, 0.0), distance_m=95.0, **timed,
                      moving_poses=(("car", 10.5, -4.0, 0.5, 270.0),),
                      camera=side, camera_id="side", size_px=(40, 30))),
        width_px=64, height_px=48,
        origin_world=(500000.0, 5400000.0, 100.0),
        background_rgb=(0.1, 0.2, 0.3),
        effects=EffectsSpec(model=effects,
                            cameras={"nadir": CameraEffectsSpec(nadir, "distortion_warp_nadir.npz"),
                                     "side": CameraEffectsSpec(fisheye, None)},
                            rig=True),
        designer_version="0.9.0", project="everything",
        light_steps=(step,),
        image_metadata="exif",
        moving_objects=(MeshSpec("car", "moving_car.npz", (grey,)),),
        vegetation=(PlantSetSpec("hedge", "plant_hedge.npz", "plants_hedge.npz", (lit, grey)),),
        wind=WindSpec(amplitude_deg=3.5, gust_period_s=4.0, direction_deg=225.0),
        tiled_texture=TiledTextureSpec(
            texture="texture.png", uv_tiles=(25.0, 25.0), interpolation="closest",
            variation="variation.png", variation_warp="variation_warp.png",
            variation_warp_uv=0.004, full_px=(20000, 21600), core_px=2048, pad_px=22,
            slots=(3, 4), digest="0123abcd", coarse="texture_tiled_coarse.tif",
            lightmap="lightmap.png", first_material=1),
    )


def _instances(value, found: dict) -> dict:
    """Every dataclass instance inside ``value``, by class."""
    if dataclasses.is_dataclass(value):
        found.setdefault(type(value), []).append(value)
        for f in dataclasses.fields(value):
            if f.init:
                _instances(getattr(value, f.name), found)
    elif isinstance(value, tuple | list):
        for v in value:
            _instances(v, found)
    elif isinstance(value, dict):
        for v in value.values():
            _instances(v, found)
    return found


def test_the_round_trip_fixture_sets_every_field_of_every_part():
    """Every dataclass a job can hold (found from RenderJob's type hints, so a new part is
    found too) appears in the fixture, each field with a default away from it somewhere."""
    found = _instances(full_job(), {})
    missing, default_only = [], []
    for cls in job_dataclasses():
        if cls not in found:
            missing.append(cls.__name__)
            continue
        for f in dataclasses.fields(cls):
            if not f.init:
                continue
            default = (f.default if f.default is not dataclasses.MISSING
                       else f.default_factory() if f.default_factory is not dataclasses.MISSING
                       else dataclasses.MISSING)
            if default is not dataclasses.MISSING and all(
                    getattr(obj, f.name) == default for obj in found[cls]):
                default_only.append(f"{cls.__name__}.{f.name}")
    assert missing == [], f"parts absent from full_job(): {missing}"
    assert default_only == [], f"fields only at their default in full_job(): {default_only}"


def test_the_job_reaches_the_effects_model_and_the_interior():
    names = {cls.__name__ for cls in job_dataclasses()}
    assert {"Effects", "Sensor", "InteriorOrientation", "BrownConrady",
            "FisheyeEquidistant", "LightStep", "PlantSetSpec", "WindSpec"} <= names


@pytest.mark.parametrize("make", [
    full_job,
    job,
    lambda: job(effects=None),
    lambda: job(render=RenderSpec(samples=16)),
    # distortion only: no effects model, a camera without distortion
    lambda: job(effects=EffectsSpec(None, {"p4p": CameraEffectsSpec(
        replace(INTERIOR, distortion=None))})),
])
def test_json_round_trip_is_exact(make):
    original = make()
    text = original.to_json()
    back = RenderJob.from_json(text)
    assert back == original
    assert back.to_json() == text
    assert back.image_names == original.image_names


def test_every_part_round_trips_with_its_own_types():
    back = RenderJob.from_json(full_job().to_json())
    spec = back.effects
    assert isinstance(spec.model, m.Effects) and isinstance(spec.model.sensor, m.Sensor)
    assert isinstance(spec.cameras["nadir"].interior.distortion, BrownConrady)
    assert isinstance(spec.cameras["side"].interior.distortion, FisheyeEquidistant)
    assert back.frames[0].moving_poses == (("car", 10.0, -4.0, 0.5, 270.0),)
    assert back.frames[1].size_px == (40, 30) and back.frames[1].camera.clip_end_m == 900.0
    assert back.frames[0].shutter_matrices_local == (MATRIX, MATRIX_LATER)
    assert back.light_steps[0].objects[0].materials[0].texture_colorspace == "Non-Color"
    assert back.vegetation[0].materials[1].color == (0.25, 0.5, 0.75)
    assert back.wind.direction_deg == 225.0


def test_a_union_of_lens_models_is_written_with_the_model_name():
    data = json.loads(full_job().to_json())
    cameras = data["effects"]["cameras"]
    assert cameras["nadir"]["interior"]["distortion"] == {
        "BrownConrady": {"k1": -0.05, "k2": 0.01, "k3": -0.001, "p1": 0.0005, "p2": -0.0003}}
    assert list(cameras["side"]["interior"]["distortion"]) == ["FisheyeEquidistant"]


def test_a_frame_without_its_optional_parts_is_written_without_them():
    data = json.loads(job().to_json())
    assert "camera" not in data["frames"][0] and "size_px" not in data["frames"][0]
    assert RenderJob.from_json(json.dumps(data)) == job()


def test_written_and_read_back_through_a_file(tmp_path):
    path = full_job().write(tmp_path / "job.json")
    assert RenderJob.read(path) == full_job()
    assert not list(tmp_path.glob(".*"))  # no temporary left beside it


def test_defaults_live_in_the_types():
    data = json.loads(job().to_json())
    del data["render"]["seed"], data["render"]["pixel_filter"], data["camera"]["clip_end_m"]
    del data["background_rgb"], data["effects"]["rig"]
    back = RenderJob.from_json(json.dumps(data))
    assert back.render.seed == 0 and back.render.pixel_filter == "BOX"
    assert back.camera.clip_end_m == 1e5 and back.background_rgb == (0.0, 0.0, 0.0)
    assert back.effects.rig is False


def _objects(data, place=""):
    """(place, object) of every JSON object inside ``data``, as the errors name places."""
    if isinstance(data, dict):
        yield place, data
        for k, v in data.items():
            inner = f"{place}[{k}]" if place.endswith("cameras") else (
                f"{place}.{k}" if place else k)
            yield from _objects(v, inner)
    elif isinstance(data, list):
        for i, v in enumerate(data):
            yield from _objects(v, f"{place}[{i}]")


def test_the_fixture_has_many_places_to_check():
    assert len(list(_objects(json.loads(full_job().to_json())))) > 30


@pytest.mark.parametrize("which", range(len(list(_objects(json.loads(full_job().to_json()))))))
def test_an_unknown_field_anywhere_is_an_error_naming_it(which):
    data = json.loads(full_job().to_json())
    place, obj = list(_objects(data))[which]
    obj["zz_stray"] = 1
    with pytest.raises(JobError) as info:
        RenderJob.from_json(json.dumps(data), "OUT/.designer-job/job.json")
    message = str(info.value)
    assert message.startswith("OUT/.designer-job/job.json: ")
    named = f"{place}[zz_stray]" if place.endswith("cameras") else (
        f"{place}.zz_stray" if place else "zz_stray")
    assert f": {named}: " in message, message


@pytest.mark.parametrize(("mutate", "fragment"), [
    (lambda d: d["render"].update(samples=0), "samples = 0"),
    (lambda d: d["render"].update(format="exr"), "image format 'exr'"),
    (lambda d: d["render"].update(stray=1), "render.stray: RenderSpec has no field 'stray'"),
    (lambda d: d["frames"][1].update(foo=2), "frames[1].foo: FrameSpec has no field 'foo'"),
    (lambda d: d["light_steps"][0]["objects"][0].update(foo=2),
     "light_steps[0].objects[0].foo: MeshSpec has no field 'foo'"),
    (lambda d: d["vegetation"][0].update(foo=2), "vegetation[0].foo: PlantSetSpec has no field"),
    (lambda d: d["wind"].update(foo=2), "wind.foo: WindSpec has no field"),
    (lambda d: d["effects"]["model"]["sensor"].update(foo=2),
     "effects.model.sensor.foo: Sensor has no field"),
    (lambda d: d["effects"]["cameras"]["side"]["interior"]["distortion"].update(
        {"Pinhole": {}}), "effects.cameras[side].interior.distortion.Pinhole: not alone"),
    (lambda d: d["effects"]["cameras"]["side"]["interior"].update(
        distortion={"Pinhole": {}}), "one key of BrownConrady, FisheyeEquidistant"),
    (lambda d: d["effects"]["cameras"]["side"]["interior"].update(image_width_px=-3),
     "image_width_px = -3 must be a positive whole number"),
    (lambda d: d["frames"][0].update(index="0"), "frames[0].index: '0' where a whole number"),
    (lambda d: d["frames"][0].update(size_px=[1, 2, 3]), "frames[0].size_px: 3 items"),
    (lambda d: d["effects"]["model"]["jpeg"].pop("quality"),
     "effects.model.jpeg.quality: Jpeg needs this field"),
    (lambda d: d["objects"][0]["materials"][0].update(color=[1, 1, 1]), "exactly one"),
    (lambda d: d.pop("frames"), "frames: RenderJob needs this field"),
    (lambda d: d["frames"].append(dict(d["frames"][0])), "repeat"),
])
def test_bad_job_files_name_the_file_and_the_problem(mutate, fragment):
    data = json.loads(full_job().to_json())
    mutate(data)
    with pytest.raises(JobError) as info:
        RenderJob.from_json(json.dumps(data), "OUT/.designer-job/job.json")
    assert fragment in str(info.value)
    assert str(info.value).startswith("OUT/.designer-job/job.json: ")


def test_a_file_that_is_not_json_is_named():
    with pytest.raises(JobError, match=r"^job\.json: not a render job"):
        RenderJob.from_json("{", "job.json")
