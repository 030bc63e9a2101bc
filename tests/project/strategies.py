"""Hypothesis strategies: random projects that are valid (schema and semantics, files aside)."""

from __future__ import annotations

import math
from datetime import datetime, timedelta, timezone

from hypothesis import strategies as st

from designer.project import model as m
from designer.project.declare import SEED_RANGE

identifiers = st.from_regex(r"[A-Za-z0-9][A-Za-z0-9_.+\-]{0,15}", fullmatch=True)
texts = (st.text(st.characters(categories=("L", "N", "P", "S", "Zs")), min_size=1, max_size=30)
         .map(str.strip).filter(bool))
paths = st.from_regex(r"[a-z]{1,8}(/[a-z0-9_]{1,8})?\.(png|jpg|ply|obj|stl|asc|tif)",
                      fullmatch=True)
seeds = st.integers(*SEED_RANGE)


def reals(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def extents(draw) -> m.Extent:
    x0, y0 = draw(reals(-1e6, 1e6)), draw(reals(-1e7, 1e7))
    w, h = draw(reals(10.0, 1e4)), draw(reals(10.0, 1e4))
    return m.Extent(x0, y0, x0 + w, y0 + h)


@st.composite
def terrains(draw) -> m.Terrain:
    extent = draw(extents())
    lo = draw(reals(-1000.0, 1000.0))
    source = draw(st.one_of(
        st.builds(m.FlatTerrain, st.just(lo)),
        st.builds(m.ProceduralTerrain, seeds, st.just(0.0), reals(0, 1),
                  st.just(lo), reals(lo, lo + 500.0)),
        st.builds(m.DemTerrain, paths),
        st.builds(m.MeshTerrain, paths),
    ))
    if isinstance(source, m.ProceduralTerrain):  # the extent is a whole number of cells
        spacing = draw(reals(0.5, 50.0))
        nx, ny = draw(st.integers(20, 200)), draw(st.integers(20, 200))
        extent = m.Extent(extent.min_X, extent.min_Y, extent.min_X + nx * spacing,
                          extent.min_Y + ny * spacing)
        source = m.ProceduralTerrain(source.seed, spacing, source.roughness,
                                     source.min_height_m, source.max_height_m)
    return m.Terrain(extent, source)


def _point_in(draw, e: m.Extent) -> tuple[float, float]:
    return (e.min_X + draw(reals(0.0, 1.0)) * e.width_m,
            e.min_Y + draw(reals(0.0, 1.0)) * e.length_m)


@st.composite
def target_sets(draw, extent: m.Extent) -> m.Targets | None:
    ids = draw(st.lists(identifiers, max_size=6, unique=True))
    if not ids and draw(st.booleans()):
        return None
    accuracy = draw(st.none() | st.builds(
        m.SurveyAccuracy, st.builds(m.Sigma3, reals(0, 1), reals(0, 1), reals(0, 1)), seeds))
    targets = []
    for target_id in ids:
        X, Y = _point_in(draw, extent)
        Z = draw(st.none() | reals(-100.0, 100.0))
        surveyed = None
        if accuracy is None or draw(st.booleans()):
            surveyed = m.SurveyedPosition(
                m.Point3(X + draw(reals(-1, 1)), Y + draw(reals(-1, 1)), draw(reals(-100, 100))),
                m.Sigma3(draw(reals(0, 1)), draw(reals(0, 1)), draw(reals(0, 1))))
        targets.append(m.Target(
            target_id, draw(st.sampled_from(["control", "check"])),
            draw(st.sampled_from(["checker", "cross", "circle", "square"])),
            draw(reals(0.01, 5.0)), m.TruePosition(X, Y, Z), surveyed))
    return m.Targets(tuple(targets), accuracy)


@st.composite
def cameras(draw, camera_id: str) -> m.Camera:
    W, H = 4 * draw(st.integers(16, 4000)), 4 * draw(st.integers(16, 4000))
    pitch = draw(reals(0.001, 0.02))
    aspect = draw(st.none() | reals(0.5, 2.0))
    sw = W * pitch
    sh = H * pitch * (aspect or 1.0)
    pixel_aspect = None if aspect is None else (sh / H) / (sw / W)
    focal = draw(reals(0.5, 2.0)) * max(sw, sh)
    distortion = draw(st.one_of(
        st.none(),
        st.builds(m.BrownConradyDistortion, reals(-0.01, 0.01), reals(-0.001, 0.001),
                  reals(-1e-4, 1e-4), reals(-1e-4, 1e-4), reals(-1e-4, 1e-4)),
        st.builds(m.FisheyeEquidistantDistortion, reals(-0.01, 0.01), reals(-0.001, 0.001),
                  reals(-1e-4, 1e-4), reals(-1e-5, 1e-5)),
    ))
    return m.Camera(
        camera_id, focal, sw, sh, W, H,
        principal_point_x_mm=draw(reals(-0.2, 0.2)) * sw,
        principal_point_y_mm=draw(reals(-0.2, 0.2)) * sh,
        pixel_aspect=pixel_aspect, distortion=distortion, name=draw(st.none() | texts),
        # a readout of 0 (a global shutter) is valid without a time line
        rolling_shutter=draw(st.none() | st.builds(
            m.RollingShutter, st.just(0.0), st.sampled_from(["top-to-bottom",
                                                             "bottom-to-top"]))))


@st.composite
def flight_plans(draw, extent: m.Extent, camera_ids: list[str]) -> m.FlightPlan:
    n = draw(st.integers(3, 8))
    cx, cy = extent.min_X + extent.width_m / 2, extent.min_Y + extent.length_m / 2
    radius = draw(reals(0.05, 0.45)) * min(extent.width_m, extent.length_m)
    turn = draw(reals(0.0, 2 * math.pi))
    area = tuple((cx + radius * math.cos(turn + 2 * math.pi * k / n),
                  cy + radius * math.sin(turn + 2 * math.pi * k / n)) for k in range(n))
    by_altitude = draw(st.booleans())
    return m.FlightPlan(
        camera=draw(st.sampled_from(camera_ids)), image_prefix=draw(identifiers), area=area,
        altitude_agl_m=draw(reals(1.0, 1000.0)) if by_altitude else None,
        gsd_m=None if by_altitude else draw(reals(0.001, 1.0)),
        front_overlap_percent=draw(reals(0, 95)), side_overlap_percent=draw(reals(0, 95)),
        grid_angle_deg=draw(reals(0, 179.9)), crosshatch=draw(st.booleans()),
        orientation=draw(st.sampled_from(["landscape", "portrait"])),
        start_corner=draw(st.sampled_from(["SW", "SE", "NW", "NE"])),
        terrain_following=draw(st.booleans()),
        altitude_reference=draw(st.sampled_from(["mean", "max", "min"]) | reals(-1000, 1000)),
        tilt_deg=draw(reals(-80, 80)),
        pose_noise=draw(st.none() | st.builds(m.PoseNoise, *[reals(0, 5)] * 6)),
        random_seed=draw(seeds))


@st.composite
def photos(draw, terrain: m.Terrain, camera_ids: list[str]) -> tuple:
    names = draw(st.lists(st.from_regex(r"[A-Za-z][A-Za-z_]{0,10}", fullmatch=True),
                          max_size=8, unique=True))
    ground = getattr(terrain.source, "height_m", getattr(terrain.source, "min_height_m", 0.0))
    return tuple(m.ExteriorOrientation(
        name, draw(st.sampled_from(camera_ids)), draw(reals(-1e6, 1e6)), draw(reals(-1e7, 1e7)),
        ground + draw(reals(1.0, 1000.0)), draw(reals(-180, 180)), draw(reals(-90, 90)),
        draw(reals(-180, 180))) for name in names)


@st.composite
def lightings(draw) -> m.Lighting:
    offset = timezone(timedelta(hours=draw(st.integers(-12, 14))))
    moment = draw(st.datetimes(datetime(1900, 1, 1), datetime(2100, 1, 1))).replace(
        tzinfo=offset)
    sun = draw(st.one_of(
        st.builds(m.Sun, reals(0, 359.99), reals(0.01, 90)),
        st.builds(m.SunPosition, st.just(moment.isoformat()), reals(-90, 90),
                  reals(-180, 180)).filter(lambda s: _daylight(s, moment))))
    return m.Lighting(sun, draw(reals(0, 1000)), draw(reals(0, 1000)))


def _daylight(sun: m.SunPosition, moment: datetime) -> bool:
    """The sun above the horizon (a valid project names a moment in daylight)."""
    from astral import Observer
    from astral.sun import elevation

    return float(elevation(Observer(latitude=sun.latitude_deg, longitude=sun.longitude_deg),
                           moment)) > 0.5


@st.composite
def effects(draw) -> m.Effects | None:
    if draw(st.booleans()):
        return None
    return m.Effects(
        vignetting=draw(st.none() | st.builds(m.Vignetting, reals(0, 0.7), st.just(0.0),
                                              st.sampled_from([0.0, -0.25]), st.booleans())),
        sensor_noise=draw(st.none() | st.builds(m.SensorNoise, reals(0, 100), seeds)),
        sensor=draw(st.none() | st.builds(m.Sensor, reals(1, 1e7), reals(0, 1e4), reals(0, 1e6),
                                          reals(0, 60), st.integers(1, 16), reals(0, 100),
                                          seeds)),
        blur=draw(st.none() | st.builds(m.Blur, reals(0, 50))),
        motion_blur=draw(st.none() | st.builds(m.MotionBlur, reals(0, 1), reals(0, 100))),
        jpeg=draw(st.none() | st.builds(m.Jpeg, st.integers(1, 100))),
        defocus=draw(st.none() | st.builds(m.Defocus, reals(0.5, 64), reals(0.1, 1e6),
                                           st.none() | reals(0.1, 1e6))),
        chromatic_aberration=draw(st.none() | st.builds(m.ChromaticAberration,
                                                        reals(-5000, 5000),
                                                        reals(-5000, 5000))))


@st.composite
def renders(draw) -> m.Render:
    fmt, depth = draw(st.sampled_from([("png", 8), ("png", 16), ("jpeg", 8), ("tiff", 8),
                                       ("tiff", 16), ("tiff", 32), ("exr", 16), ("exr", 32)]))
    return m.Render(
        preset=draw(st.sampled_from(["draft", "survey", "metrology"])),
        samples=draw(st.none() | st.integers(1, 65536)),
        pixel_filter_type=draw(st.sampled_from(["box", "gaussian", "blackman-harris"])),
        pixel_filter_width_px=draw(reals(0.01, 10)),
        resolution_scale=draw(st.sampled_from([1.0, 0.5, 0.25])),
        workers=draw(st.integers(1, 256)), output_format=fmt, bit_depth=depth,
        distortion_oversample=draw(st.integers(1, 4)))


@st.composite
def processings(draw, target_ids: list[str]) -> m.Processing | None:
    if draw(st.booleans()):
        return None
    pre = draw(st.none() | st.builds(m.PreCalibrationError, reals(0, 100), reals(0, 50),
                                     reals(0, 0.1), reals(0, 0.1), reals(0, 0.1),
                                     reals(0, 0.01), reals(0, 0.01), seeds))
    mode = draw(st.sampled_from(["none", "similarity", "bundle"]))
    control = None
    if target_ids and draw(st.booleans()):
        if mode == "similarity" and len(target_ids) < 3:
            mode = "bundle"
        low = 3 if mode == "similarity" else 1
        if draw(st.booleans()):
            ids = draw(st.lists(st.sampled_from(target_ids), min_size=low, unique=True))
            control = m.ControlSelection(tuple(ids), None, "even", draw(seeds))
        else:
            control = m.ControlSelection((), draw(st.integers(low, len(target_ids))),
                                         draw(st.sampled_from(["even", "random"])), draw(seeds))
    return m.Processing(
        m.Calibration(draw(st.sampled_from(["fixed", "focal", "focal-principal-point",
                                            "radial", "full"])), pre),
        m.GcpProcessing(mode, draw(reals(0, 50)), draw(seeds), control),
        m.PositionPrior(draw(st.sampled_from(["none", "gnss", "rtk"])),
                        draw(st.none() | reals(1e-3, 1000)), draw(st.none() | reals(1e-3, 1000)),
                        draw(seeds)),
        m.Matching(draw(st.integers(100, 10**6)),
                   draw(st.sampled_from(["footprint", "position", "exhaustive"])),
                   draw(st.integers(2, 100))),
        draw(st.sampled_from(["none", "cpu", "auto"])))


@st.composite
def projects(draw) -> m.Project:
    terrain = draw(terrains())
    repeat_X, repeat_Y = draw(st.integers(1, 50)), draw(st.integers(1, 50))
    tile = max(terrain.extent.width_m / repeat_X, terrain.extent.length_m / repeat_Y)
    source = draw(st.one_of(
        st.builds(m.ImageTexture, paths),
        st.builds(m.ProceduralTexture,
                  st.sampled_from(["grass", "soil", "gravel", "noise", "checkerboard",
                                   "slanted-edge"]),
                  seeds, reals(17, 8000).map(lambda n: tile / n)),
        st.builds(m.OrthophotoTexture, paths)))
    if isinstance(source, m.OrthophotoTexture):
        repeat_X = repeat_Y = 1  # an orthophoto is placed by its geotransform, never tiled
    texture = m.Texture(source, repeat_X, repeat_Y, draw(st.sampled_from(["closest", "linear"])))
    camera_ids = draw(st.lists(identifiers, min_size=1, max_size=3, unique=True))
    cams = tuple(draw(cameras(cid)) for cid in camera_ids)
    shots = draw(photos(terrain, camera_ids))
    plan = draw(st.none() | flight_plans(terrain.extent, camera_ids)) if shots else \
        draw(flight_plans(terrain.extent, camera_ids))
    objects = tuple(
        m.SceneObject(name, draw(paths), m.Placement(
            m.Point3(draw(reals(-1e6, 1e6)), draw(reals(-1e6, 1e6)), draw(reals(-100, 100))),
            draw(reals(-360, 360)), draw(reals(-360, 360)), draw(reals(-360, 360)),
            draw(reals(0.001, 1000))))
        for name in draw(st.lists(identifiers, max_size=3, unique=True)))
    formats = draw(st.lists(st.sampled_from(["colmap", "odm", "metashape", "opk", "gcp"]),
                            unique=True))
    # OpenDroneMap needs a projected CRS in metres it can parse (UTM zones north and
    # south, ETRS89 / UTM, Swiss LV95); other formats take any label.
    crs = (draw((st.integers(32601, 32660) | st.integers(32701, 32760) | st.integers(25828, 25838)
                 | st.just(2056)).map(lambda c: f"EPSG:{c}"))
           + draw(st.sampled_from(["", " (a projected CRS)"])) if "odm" in formats
           else draw(texts))
    targets = draw(target_sets(terrain.extent))
    target_ids = [t.id for t in targets.targets] if targets else []
    return m.Project(
        name=draw(texts), description=draw(st.none() | texts), crs=crs,
        origin=m.Origin(draw(reals(-1e7, 1e7)), draw(reals(-1e7, 1e7)), draw(reals(-1e3, 1e4))),
        scene=m.Scene(terrain, texture, draw(lightings()),
                      targets, objects),
        cameras=cams, trajectory=m.Trajectory(shots, plan), effects=draw(effects()),
        render=draw(renders()), outputs=m.Outputs(draw(paths), tuple(formats)),
        processing=draw(processings(target_ids)))
