"""Flight planner: parallel-line (lawn-mower) surveys over a polygon, and pose noise.

Frames: world X = east, Y = north, Z = up (metres, float64; UTM-sized areas are planned
relative to the area's centroid, so a shifted area gives the same plan shifted).
Azimuths are degrees clockwise from north. Each station carries the perspective centre
``C_world`` (3,) and ``R_cam_to_world`` (3, 3) of docs/conventions.md.

Formulas (QGroundControl's CameraCalc, square pixels, nadir camera at height H above
ground, f focal length, sw × sh sensor, W × H_img image; pitch = sw/W):

* GSD = H · pitch / f  (so H = GSD · f / pitch when a GSD is requested);
* landscape (the default): the long image side, the image width, lies across track:
  footprint across = W · GSD = H · sw / f, along = H_img · GSD = H · sh / f;
  portrait swaps them;
* line spacing = footprint across · (1 − side overlap);
* trigger distance = footprint along · (1 − front overlap).

Overlaps are *fractions* in [0, 1) — 80 % is 0.8.

Camera orientation (decision): landscape puts the image top along the flight
direction (heading = flight azimuth, image right = right of track); portrait puts the
image right along the flight direction (heading = flight azimuth − 90°). The heading
follows each line, so the camera turns 180° on the return lines, as a drone's
camera does. A forward tilt turns the viewing axis from nadir towards the flight
direction: ``rotation_from_heading_tilt_roll(azimuth, tilt, 0)`` in landscape,
``(azimuth − 90°, 0, tilt)`` in portrait.

Coverage rule (decision): the area's edges are covered as well as its middle. On flat
ground with a nadir camera a point in the middle of an endless grid lies inside at
least N = ⌊footprint / step⌋ images along track (⌊1/(1 − front)⌋) and as many lines
across track (⌊1/(1 − side)⌋). Across track, the planner takes the fewest lines at the
line spacing, laid out symmetrically about the middle of the area's across-track
extent w, that put every point of the area, edges included, inside at least N line
footprints: n = ⌊(w − A)/s + 2·(N − 1)⌋ + 2 for footprint A and step s. (A Phantom 4
Pro at 100 m with 70 % side overlap over a 400 m wide area: A = 150 m, s = 45 m,
N = 3, n = 11 lines, the outermost 25 m outside the edges.) Every line's footprint
reaches into the area. Along track, each line runs over w = the along-track extent of
the part of the area inside its footprint strip (width A), grown at both ends by
H·tan(tilt) for an oblique camera, and gets its stations by the same rule at the
trigger distance. A line across a concave gap is flown straight through it. Lines are
flown in serpentine order from the requested start corner. A crosshatch adds a
second grid at grid angle + 90°, started from whichever end of its first or last line
is nearest the end of the first grid.

Altitude (decision): ``"terrain_following"`` puts every station the AGL height above
the terrain directly below it (bilinear height; stations past the terrain's edge use
the height at the nearest edge point). ``"constant"`` flies every station at one height
Z = reference + AGL, where the reference is the mean, max or min terrain height over
the nodes inside the area, or a given height (m, world Z). Spacing and trigger
distance always use the AGL height, so above a "mean" reference the GSD and
overlaps vary with the terrain (higher ground: finer GSD, less overlap).
Spacing and trigger distance use the nadir formulas also for an oblique camera (as
QGroundControl does). Its ground footprint is longer, but the share of *image area*
that overlaps (what :mod:`designer.survey.coverage` measures) drops below the request,
because the near part of a tilted image sweeps over the ground fastest: on flat ground
with 80 %/70 % requested, a 20° forward tilt gives about 72 % front overlap in
landscape (68 % front and side in portrait). Ask for more overlap when flying oblique,
and check the plan with the coverage analysis.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.core.rotation import perturb_rotation, rotation_from_heading_tilt_roll
from designer.errors import DesignerError, ParameterError
from designer.survey import area as _area

ORIENTATIONS = ("landscape", "portrait")
ALTITUDE_MODES = ("terrain_following", "constant")
ALTITUDE_REFERENCES = ("mean", "max", "min")
#: compass corners for ``start_corner`` as (east, north) signs
START_CORNERS = {"SW": (-1, -1), "SE": (1, -1), "NW": (-1, 1), "NE": (1, 1)}
#: largest accepted forward tilt (deg); beyond it the footprint reaches the horizon
MAX_TILT_DEG = 80.0


@dataclass(frozen=True)
class CameraCalc:
    """QGroundControl's CameraCalc numbers, in metres (GSD in m/px)."""

    altitude_agl_m: float
    gsd_m: float
    footprint_across_m: float
    footprint_along_m: float
    line_spacing_m: float
    trigger_distance_m: float


def camera_calc(
    interior: InteriorOrientation,
    *,
    altitude_agl_m: float | None = None,
    gsd_m: float | None = None,
    front_overlap_fraction: float,
    side_overlap_fraction: float,
    orientation: str = "landscape",
) -> CameraCalc:
    """Altitude/GSD, footprints, line spacing and trigger distance (module docstring).

    Give exactly one of ``altitude_agl_m`` (m above ground) and ``gsd_m`` (m/px).
    """
    front = _overlap(front_overlap_fraction, "front_overlap_fraction")
    side = _overlap(side_overlap_fraction, "side_overlap_fraction")
    if orientation not in ORIENTATIONS:
        raise DesignerError(f"orientation {orientation!r} must be one of {ORIENTATIONS}")
    pitch_m = interior.pixel_pitch_x_mm / 1000.0
    f_m = interior.focal_length_mm / 1000.0
    if (altitude_agl_m is None) == (gsd_m is None):
        raise DesignerError("give either a flight height above ground or a target GSD, not both")
    if gsd_m is not None:
        if not (math.isfinite(gsd_m) and gsd_m > 0):
            raise ParameterError(f"target GSD = {gsd_m} m/px must be > 0", name="gsd_m",
                                 value=gsd_m, unit="m", must="greater than 0 m")
        altitude_agl_m = gsd_m * f_m / pitch_m
    assert altitude_agl_m is not None
    if not (math.isfinite(altitude_agl_m) and altitude_agl_m > 0):
        raise ParameterError(
            f"flight height above ground = {altitude_agl_m} m must be > 0 m",
            name="altitude_agl_m", value=altitude_agl_m, unit="m", must="greater than 0 m")
    gsd = altitude_agl_m * pitch_m / f_m
    width_m = altitude_agl_m * interior.sensor_width_mm / interior.focal_length_mm
    height_m = altitude_agl_m * interior.sensor_height_mm / interior.focal_length_mm
    across, along = (width_m, height_m) if orientation == "landscape" else (height_m, width_m)
    return CameraCalc(
        altitude_agl_m=float(altitude_agl_m), gsd_m=float(gsd),
        footprint_across_m=float(across), footprint_along_m=float(along),
        line_spacing_m=float(across * (1.0 - side)),
        trigger_distance_m=float(along * (1.0 - front)),
    )


@dataclass(frozen=True, eq=False)
class Station:
    """One exposure of a flight plan.

    Attributes:
        image_name: file name the render will write.
        C_world: (3,) perspective centre, world metres (read-only array).
        R_cam_to_world: (3, 3) camera → world rotation (read-only array).
        line_index: flight line, counted across both grids in flight order (0-based).
        grid_index: 0 for the main grid, 1 for the crosshatch grid.
        flight_azimuth_deg: direction flown along this line, clockwise from north.
    """

    image_name: str
    C_world: np.ndarray
    R_cam_to_world: np.ndarray
    line_index: int
    grid_index: int
    flight_azimuth_deg: float

    def __post_init__(self) -> None:
        for name, shape in (("C_world", (3,)), ("R_cam_to_world", (3, 3))):
            a = np.array(getattr(self, name), dtype=float)
            if a.shape != shape:
                raise ValueError(f"{name} must have shape {shape}, got {a.shape}")
            a.flags.writeable = False
            object.__setattr__(self, name, a)


@dataclass(frozen=True, eq=False)
class FlightPlan:
    """A planned survey: the stations in flight order and the numbers behind them.

    ``reference_height_m`` is the Z the constant-altitude plan flies above (None for
    terrain following). To swap in noisy poses:
    ``dataclasses.replace(plan, stations=tuple(apply_pose_noise(plan.stations, ...)))``.
    """

    stations: tuple[Station, ...]
    calc: CameraCalc
    grid_angle_deg: float
    crosshatch: bool
    n_lines: int
    altitude_mode: str
    reference_height_m: float | None
    orientation: str
    forward_tilt_deg: float
    area: np.ndarray = field(repr=False)

    @property
    def C_world(self) -> np.ndarray:
        """(M, 3) perspective centres."""
        return np.array([s.C_world for s in self.stations]).reshape(-1, 3)

    @property
    def R_cam_to_world(self) -> np.ndarray:
        """(M, 3, 3) rotations."""
        return np.array([s.R_cam_to_world for s in self.stations]).reshape(-1, 3, 3)

    @property
    def line_index(self) -> np.ndarray:
        return np.array([s.line_index for s in self.stations], dtype=int)

    @property
    def image_names(self) -> list[str]:
        return [s.image_name for s in self.stations]


def plan_flight(
    area,
    interior: InteriorOrientation,
    *,
    altitude_agl_m: float | None = None,
    gsd_m: float | None = None,
    front_overlap_fraction: float = 0.8,
    side_overlap_fraction: float = 0.7,
    grid_angle_deg: float = 0.0,
    crosshatch: bool = False,
    heightfield: Heightfield | None = None,
    altitude_mode: str = "constant",
    altitude_reference: str | float = "mean",
    forward_tilt_deg: float = 0.0,
    orientation: str = "landscape",
    start_corner: str = "SW",
    image_name_format: str = "IMG_{index:05d}.png",
    first_index: int = 1,
    max_stations: int = 100_000,
) -> FlightPlan:
    """Plan a parallel-line survey of ``area`` (a polygon, world XY metres).

    grid_angle_deg is the azimuth of the flight lines (clockwise from north; lines are
    flown both ways). ``heightfield`` is needed for terrain following and for a
    named altitude reference. Image names are ``image_name_format.format(index=k)``
    with k counting from ``first_index`` in flight order. Raises DesignerError for
    impossible requests, including plans of more than ``max_stations`` images.
    See the module docstring for the formulas and rules.
    """
    calc = camera_calc(interior, altitude_agl_m=altitude_agl_m, gsd_m=gsd_m,
                       front_overlap_fraction=front_overlap_fraction,
                       side_overlap_fraction=side_overlap_fraction, orientation=orientation)
    poly = _area.as_polygon(area)
    if not math.isfinite(grid_angle_deg):
        raise ParameterError(f"grid angle = {grid_angle_deg} must be a finite number of degrees",
                             name="grid_angle_deg", value=grid_angle_deg,
                             must="a finite number of degrees")
    if not (math.isfinite(forward_tilt_deg) and abs(forward_tilt_deg) <= MAX_TILT_DEG):
        raise ParameterError(
            f"forward tilt = {forward_tilt_deg} deg must lie within +-{MAX_TILT_DEG:g} deg",
            name="tilt_deg", value=forward_tilt_deg, unit="deg",
            must=f"from -{MAX_TILT_DEG:g} to {MAX_TILT_DEG:g} °")
    if start_corner not in START_CORNERS:
        raise DesignerError(f"start corner {start_corner!r} must be one of {list(START_CORNERS)}")
    reference = _reference_height(poly, heightfield, altitude_mode, altitude_reference)
    try:
        distinct = image_name_format.format(index=1) != image_name_format.format(index=2)
    except (KeyError, IndexError, ValueError) as error:
        raise DesignerError(f"image name format {image_name_format!r}: {error}") from None
    if not distinct:
        raise DesignerError(
            f"image name format {image_name_format!r} must contain {{index}}, e.g. "
            f"'IMG_{{index:05d}}.png'")

    origin = _area.polygon_centroid(poly)
    local = poly - origin
    extension = calc.altitude_agl_m * abs(math.tan(math.radians(forward_tilt_deg)))
    corner = np.array(START_CORNERS[start_corner], dtype=float)
    grids = [_grid_lines(local, grid_angle_deg, calc, extension, corner)]
    if crosshatch:
        last = grids[0][-1][0][-1]  # last station of the first grid
        grids.append(_grid_lines(local, grid_angle_deg + 90.0, calc, extension, last, True))
    total = sum(len(xy) for lines in grids for xy, _ in lines)
    if total > max_stations:
        raise DesignerError(
            f"this plan needs {total} images, more than the limit of {max_stations}; fly "
            f"higher (coarser GSD), lower the overlaps, or raise the limit")

    stations: list[Station] = []
    line_index = 0
    for grid_index, lines in enumerate(grids):
        for xy_local, azimuth in lines:
            xy = xy_local + origin
            if reference is None:
                assert heightfield is not None
                z = _ground_below(heightfield, xy) + calc.altitude_agl_m
            else:
                z = np.full(len(xy), reference + calc.altitude_agl_m)
            R = _camera_rotation(azimuth, forward_tilt_deg, orientation)
            for p, zk in zip(xy, z, strict=True):
                name = image_name_format.format(index=first_index + len(stations))
                stations.append(Station(name, np.array([p[0], p[1], zk]), R, line_index,
                                        grid_index, float(azimuth % 360.0)))
            line_index += 1
    return FlightPlan(
        stations=tuple(stations), calc=calc, grid_angle_deg=float(grid_angle_deg),
        crosshatch=bool(crosshatch), n_lines=line_index, altitude_mode=altitude_mode,
        reference_height_m=reference, orientation=orientation,
        forward_tilt_deg=float(forward_tilt_deg), area=poly,
    )


def apply_pose_noise(
    stations: Sequence[Station],
    sigma_xyz_m,
    sigma_opk_deg,
    seed: int,
) -> list[Station]:
    """New stations with Gaussian pose errors; the input is not modified.

    Position: C' = C + ε, ε ~ N(0, diag(σx², σy², σz²)) in world X, Y, Z (m).
    Rotation: R' = R · Exp(δ), δ ~ N(0, σ²) independently about the camera's own x, y
    and z axes (``sigma_opk_deg``, degrees). For a nadir camera with the image top
    north (R = I) these are small changes of ω, φ and κ; for any other attitude they
    stay rotations about the camera axes, so the noise is the same for every station
    and never meets the Euler singularity. The same seed gives the same noise.
    """
    sigma_xyz = _sigmas(sigma_xyz_m, "sigma_xyz_m")
    sigma_rad = np.radians(_sigmas(sigma_opk_deg, "sigma_opk_deg"))
    rng = np.random.default_rng(seed)
    if len(stations) == 0:
        return []
    C = np.array([s.C_world for s in stations])
    R = np.array([s.R_cam_to_world for s in stations])
    C_new = C + rng.standard_normal(C.shape) * sigma_xyz
    R_new = perturb_rotation(R, sigma_rad, rng)
    return [replace(s, C_world=c, R_cam_to_world=r)
            for s, c, r in zip(stations, C_new, R_new, strict=True)]


# ----------------------------------------------------------------------------- helpers
def _overlap(value: float, name: str) -> float:
    if not math.isfinite(value) or value < 0:
        raise ParameterError(f"{name} = {value} must be a fraction in [0, 1)", name=name,
                             value=value, must="a fraction from 0 to below 1")
    if 1.0 < value < 100.0:
        raise ParameterError(
            f"{name} = {value} must be a fraction in [0, 1), not a percentage; "
            f"{value:g} % is written {value / 100:g}", name=name, value=value,
            must=f"a fraction from 0 to below 1, not a percentage ({value:g} % is "
                 f"{value / 100:g})")
    if value >= 1.0:
        raise ParameterError(
            f"{name} = {value}: an overlap of 100 % or more never moves on; use a "
            f"fraction below 1", name=name, value=value,
            must="a fraction below 1 (an overlap of 100 % or more never moves on)")
    return float(value)


def _sigmas(value, name: str) -> np.ndarray:
    s = np.broadcast_to(np.asarray(value, dtype=float), (3,)).copy()
    if not np.all(np.isfinite(s) & (s >= 0)):
        raise DesignerError(f"{name} = {value!r} must be three standard deviations >= 0")
    return s


def _reference_height(poly, heightfield, mode, reference) -> float | None:
    if mode not in ALTITUDE_MODES:
        raise DesignerError(f"altitude mode {mode!r} must be one of {ALTITUDE_MODES}")
    if mode == "terrain_following" or isinstance(reference, str):
        if heightfield is None:
            what = ("terrain following" if mode == "terrain_following"
                    else f"the altitude reference {reference!r}")
            raise DesignerError(f"{what} needs the terrain (a height field); none was given")
        x0, x1, y0, y1 = heightfield.extent_m
        lo, hi = poly.min(axis=0), poly.max(axis=0)
        if hi[0] < x0 or lo[0] > x1 or hi[1] < y0 or lo[1] > y1:
            raise DesignerError("the survey area lies entirely outside the terrain")
    if mode == "terrain_following":
        return None
    if not isinstance(reference, str):
        if not math.isfinite(reference):
            raise DesignerError(f"altitude reference = {reference} must be a finite height")
        return float(reference)
    if reference not in ALTITUDE_REFERENCES:
        raise DesignerError(
            f"altitude reference {reference!r} must be one of {ALTITUDE_REFERENCES} or a "
            f"height in metres")
    return _reference_of(heightfield, poly, reference)


#: the last few reference heights: (height grid, its placement, the area, the
#: reference) → m. The height grid is held weakly, so a terrain let go is forgotten.
_REFERENCES: list[tuple] = []
#: how many are kept (an edit plans the flight twice, for the stations and the images)
_KEPT_REFERENCES = 4


def _reference_of(hf: Heightfield, poly: np.ndarray, reference: str) -> float:
    """The mean, max or min height of ``hf`` inside ``poly`` (m). Kept for the same
    height grid and area: an edit of the flight's height or overlaps leaves it as it
    was, and over a 5,000-image block's 4.6 M nodes it was most of the window's
    stations job (1.6 s of each plan)."""
    import weakref

    key = (hf.x0_m, hf.y0_m, hf.dx_m, hf.dy_m, np.asarray(poly, float).tobytes(), reference)
    for grid, k, value in list(_REFERENCES):
        if grid() is hf.heights_m and k == key:
            return value
    z = _heights_inside(hf, poly)
    value = float({"mean": np.mean, "max": np.max, "min": np.min}[reference](z))
    _REFERENCES.insert(0, (weakref.ref(hf.heights_m), key, value))
    del _REFERENCES[_KEPT_REFERENCES:]
    return value


def _heights_inside(hf: Heightfield, poly: np.ndarray) -> np.ndarray:
    ny, nx = hf.heights_m.shape
    lo, hi = poly.min(axis=0), poly.max(axis=0)
    j0, j1 = (np.clip(np.array([lo[0], hi[0]]) - hf.x0_m, 0, None) / hf.dx_m).astype(int)
    i0, i1 = (np.clip(np.array([lo[1], hi[1]]) - hf.y0_m, 0, None) / hf.dy_m).astype(int)
    j1, i1 = min(j1 + 1, nx - 1), min(i1 + 1, ny - 1)
    z = hf.heights_m[i0:i1 + 1, j0:j1 + 1]
    inside = _area.contains_grid(poly, hf.x0_m + np.arange(j0, j1 + 1) * hf.dx_m,
                                 hf.y0_m + np.arange(i0, i1 + 1) * hf.dy_m).ravel()
    if inside.any():
        return z.ravel()[inside]
    # an area smaller than a grid cell: sample its vertices and centroid instead
    pts = np.vstack([poly, _area.polygon_centroid(poly)])
    h = hf.height_at(pts[:, 0], pts[:, 1])
    return h[np.isfinite(h)] if np.isfinite(h).any() else _ground_below(hf, pts)


def _ground_below(hf: Heightfield, xy: np.ndarray) -> np.ndarray:
    x0, x1, y0, y1 = hf.extent_m
    return hf.height_at(np.clip(xy[:, 0], x0, x1), np.clip(xy[:, 1], y0, y1))


def _camera_rotation(azimuth_deg: float, tilt_deg: float, orientation: str) -> np.ndarray:
    a, t = math.radians(azimuth_deg), math.radians(tilt_deg)
    if orientation == "landscape":
        return rotation_from_heading_tilt_roll(a, t, 0.0)
    return rotation_from_heading_tilt_roll(a - math.pi / 2, 0.0, t)


def _grid_lines(local, angle_deg, calc: CameraCalc, extension_m, start, start_is_point=False):
    """Lines of one grid as [(xy (n, 2) local, azimuth_deg)] in flight order.

    The grid starts at one end of its first or last line: with a compass corner
    ``start`` (east, north signs) the end farthest that way; with ``start_is_point``
    (a local XY point) the end nearest to it.
    """
    d, r = _area.azimuth_axes(angle_deg)
    a, c = local @ d, local @ r
    half = calc.footprint_across_m / 2
    offsets = _covering_steps(float(c.min()), float(c.max()), calc.footprint_across_m,
                              calc.line_spacing_m)
    runs = []
    for off in offsets:
        span = _strip_extent(a, c, off - half, off + half)
        if span is not None:
            runs.append((off, span[0] - extension_m, span[1] + extension_m))
    if not runs:
        raise DesignerError("no flight line crosses the area")
    corners = [(ci, ai) for ci in (0, -1) for ai in (0, 1)]  # (first/last line, end)

    def corner_xy(ci, ai):
        off, a0, a1 = runs[ci]
        return (a0, a1)[ai] * d + off * r

    if start_is_point:
        score = [-float(np.hypot(*(corner_xy(*k) - start))) for k in corners]
    else:
        score = [float(corner_xy(*k) @ start) for k in corners]
    first_line, first_end = corners[int(np.argmax(score))]
    if first_line == -1:
        runs = runs[::-1]
    out = []
    for k, (off, a0, a1) in enumerate(runs):
        pos = _covering_steps(a0, a1, calc.footprint_along_m, calc.trigger_distance_m)
        forward = (k % 2 == 0) == (first_end == 0)
        if not forward:
            pos = pos[::-1]
        xy = pos[:, None] * d + off * r
        out.append((xy, angle_deg if forward else angle_deg + 180.0))
    return out


def _covering_steps(lo: float, hi: float, footprint: float, step: float) -> np.ndarray:
    """Positions ``step`` apart, centred on [lo, hi], as few as put every point of it
    inside at least N = ⌊footprint/step⌋ footprints (module docstring)."""
    n_min = math.floor(footprint / step + 1e-9)
    n = max(1, math.floor((hi - lo - footprint) / step + 2 * (n_min - 1) + 1e-9) + 2)
    return (lo + hi) / 2 + (np.arange(n) - (n - 1) / 2) * step


def _strip_extent(a, c, c_lo, c_hi):
    """(min, max) along-track coordinate of the polygon's part with c_lo ≤ c ≤ c_hi."""
    vals = list(a[(c >= c_lo) & (c <= c_hi)])
    a2, c2 = np.roll(a, -1), np.roll(c, -1)
    for level in (c_lo, c_hi):
        cross = (c - level) * (c2 - level) < 0
        t = (level - c[cross]) / (c2[cross] - c[cross])
        vals.extend(a[cross] + t * (a2[cross] - a[cross]))
    if not vals:
        return None
    return float(min(vals)), float(max(vals))
