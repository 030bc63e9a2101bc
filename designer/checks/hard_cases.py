"""Warnings for projects that walk into a case that degrades results (docs/hard-cases.md).

Each warning is a :class:`HardCaseWarning`: the element at fault, what goes wrong with
its size, and the fix. ``designer check`` prints them; none of them makes a project
invalid (the invalid cases — a lens map that folds inside the image, control on one
exact line — are refused where they are read or used).

* control GCPs nearly collinear: a similarity (or a datum from control) cannot fix the
  rotation about the line they lie on; :func:`point_spread` measures it;
* the GSD finer than the texture's texel (the texture is magnified, features repeat) and,
  the other way, texels finer than a third of the GSD (the plan's aliasing warning,
  designer.checks.plan_report, reused);
* a lens whose image corners come close to the radius where its radial map stops being
  monotonic: undistortion magnifies pixel errors there;
* networks too thin for structure from motion: fewer than 3 images, every image on one
  flight line, a front overlap under half the footprint (:func:`network_warnings`);
* optics beyond any survey camera: a pinhole lens wider than 120° across, a flight whose
  GSD is coarser than 1 m (:func:`optics_warnings`).

``designer plan`` prints the collinear control and the network's warnings too
(:func:`control_and_network_warnings`; over a terrain mesh, which it cannot analyse,
before it refuses).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError
from designer.project import model as m

#: control whose largest/second-largest spread exceeds this (width < length / 10) is
#: reported: with 1 cm marking noise the rotation about the line is off by ~0.1°
COLLINEAR_WARN_CONDITION = 10.0
#: control this close to one line is refused by the similarity: 5 points 35 cm off a
#: 100 m line; at 5 cm off it RANSAC returned a similarity 6° wrong without a word
COLLINEAR_REFUSE_CONDITION = 100.0
#: radial magnification 1/g'(r) of pixel errors by undistortion at the image corner
DISTORTION_WARN_MAGNIFICATION = 2.0


@dataclass(frozen=True)
class HardCaseWarning:
    element: str  #: the element at fault, e.g. "targets"
    message: str  #: what goes wrong, with its size
    fix: str
    #: the fix in the window's words (its panels and fields), where ``fix`` names the
    #: file's elements and attributes; None: ``fix`` reads the same in both
    panel_fix: str | None = None

    def line(self, path: Path | str) -> str:
        """``warning: PATH: <element>: message; fix`` (one line)."""
        return f"warning: {path}: <{self.element}>: {self.message}; {self.fix}"


@dataclass(frozen=True)
class PointSpread:
    """How far points (N, 3), metres, are from lying on one line."""

    length_m: float  #: extent along the first principal axis
    width_m: float  #: extent along the second principal axis (the strip's width)
    condition: float  #: first / second singular value of the centred points (inf: a line)


def point_spread(xyz_m: np.ndarray) -> PointSpread:
    """The spread of points (N, 3) in metres, centred first (UTM-sized input keeps its
    precision)."""
    xyz = np.asarray(xyz_m, dtype=np.float64)
    if xyz.ndim != 2 or xyz.shape[1] != 3 or len(xyz) < 2:
        raise ValueError(f"points must be shaped (N >= 2, 3), got {xyz.shape}")
    centred = xyz - xyz.mean(axis=0)
    _, s, Vt = np.linalg.svd(centred, full_matrices=False)
    along = centred @ Vt[0]
    across = centred @ Vt[1]
    condition = math.inf if s[1] <= 1e-12 * max(s[0], 1e-300) else float(s[0] / s[1])
    return PointSpread(float(np.ptp(along)), float(np.ptp(across)), condition)


def collinear_problem(xyz_m: np.ndarray, what: str,
                      threshold: float = COLLINEAR_REFUSE_CONDITION) -> str | None:
    """One sentence if fewer than 3 points or the points (N, 3) lie so close to one line
    (condition number above ``threshold``) that a similarity fitted on them cannot fix the
    rotation about it; None otherwise."""
    xyz = np.asarray(xyz_m, dtype=np.float64)
    if len(xyz) < 3:
        return f"only {len(xyz)} {what}; a similarity needs at least 3 not on one line"
    s = point_spread(xyz)
    if s.condition <= threshold:
        return None
    return (f"the {len(xyz)} {what} lie on one line ({s.length_m:.2f} m long, a strip "
            f"{s.width_m:.3g} m wide, condition number {s.condition:.3g}): the rotation "
            "about that line is undetermined; add control off the line (at least a tenth "
            "of its length away)")


def control_warning(targets) -> HardCaseWarning | None:
    """The warning for nearly collinear control (``targets``: designer.scene.build's
    BuiltTarget, their surveyed coordinates)."""
    control = [t for t in targets if t.target.role == "control"]
    return collinear_control_warning([t.target.id for t in control],
                                     [t.surveyed_xyz for t in control])


def collinear_control_warning(ids, surveyed_xyz_m) -> HardCaseWarning | None:
    """The warning for nearly collinear control: the control GCPs ``ids`` surveyed at
    ``surveyed_xyz_m`` (N, 3), metres; None below 3 of them or when they spread enough."""
    if len(ids) < 3:
        return None
    s = point_spread(np.asarray(surveyed_xyz_m, dtype=np.float64))
    if s.condition <= COLLINEAR_WARN_CONDITION:
        return None
    return HardCaseWarning(
        "targets",
        f"the {len(ids)} control GCPs ({', '.join(ids)}) are nearly collinear: they span a "
        f"strip {s.width_m:.3g} m wide and {s.length_m:.1f} m long (condition number "
        f"{s.condition:.3g}); the rotation about that line is fixed only by the strip's "
        f"width, so errors grow with the distance from it",
        "move or add control GCPs off the line, at least a tenth of its length away")


def finest_gsd_m(project: m.Project, hf, images, raycaster=None) -> float:
    """The finest GSD (m/px) any image of ``images`` (designer.survey.project_poses) has
    on the height field ``hf``, sampled at a 3 × 3 grid of pixels per image: the slant
    distance along the optical axis × pixel pitch / focal length. NaN if no ray meets it.
    ``raycaster``: a :class:`designer.core.raycast.TerrainRaycaster` over ``hf`` the
    caller holds already (else one is built)."""
    from designer.core.projection import ground_sample_distance_m
    from designer.core.rotation import R_CV_FROM_PHOTO
    from designer.errors import NotInvertibleError
    from designer.project.interiors import render_interior

    starts, rays, axes, pitch_over_f = [], [], [], []
    # each camera's rays once (inverting the distortion per image was 5 s of the plan
    # figures at 5,000 images), turned by each image's rotation as pixel_rays_world does,
    # all images of the camera at once
    for camera_id in images.camera_order():
        io = render_interior(project.camera(camera_id), project.render.resolution_scale)
        W, H = io.image_size_px
        g = np.linspace(0.05, 0.95, 3)
        uv = np.stack(np.meshgrid(g * W, g * H), axis=-1).reshape(-1, 2)
        try:
            rays_cv = io.rays_cv(uv)
        except NotInvertibleError:
            continue
        k = [i for i, c in enumerate(images.camera_ids) if c == camera_id]
        R = np.array([images.stations[i].R_cam_to_world for i in k], float).reshape(-1, 3, 3)
        C = np.array([images.stations[i].C_world for i in k], float).reshape(-1, 3)
        n = len(k) * len(uv)
        rays.append(np.matmul(rays_cv, np.swapaxes(R @ R_CV_FROM_PHOTO, 1, 2)).reshape(n, 3))
        starts.append(np.repeat(C, len(uv), axis=0))
        axes.append(np.repeat(-R[:, :, 2], len(uv), axis=0))
        pitch_over_f.append(np.full(n, float(ground_sample_distance_m(io, 1.0))))
    if not rays:
        return math.nan
    C = np.concatenate(starts)
    from designer.core.raycast import TerrainRaycaster

    rc = raycaster if raycaster is not None else TerrainRaycaster(hf)
    hits = rc.surface_hit(C, np.concatenate(rays), tol_m=1e-6)
    depth = np.einsum("ij,ij->i", hits - C, np.concatenate(axes))
    gsd = depth * np.concatenate(pitch_over_f)
    gsd = gsd[np.isfinite(gsd) & (gsd > 0)]
    return float(gsd.min()) if gsd.size else math.nan


#: texels finer than GSD / this alias: pixels average several texels, features do not repeat
ALIASING_RATIO = 3.0


def aliasing_warning(source, gsd_min_m: float) -> str | None:
    """A procedural texture whose texels are finer than a third of the finest GSD (m/px):
    the plan report's and ``designer check``'s one wording of it."""
    if isinstance(source, m.ProceduralTexture) and source.texel_size_m < gsd_min_m / ALIASING_RATIO:
        return (f"texture texels ({100 * source.texel_size_m:.1f} cm) are finer than a third "
                f"of the GSD ({100 * gsd_min_m:.1f} cm): pixels will alias the texture and "
                "SIFT features will not repeat between images; use a texel near GSD/2")
    return None


def texture_warnings(project: m.Project, gsd_min_m: float) -> list[HardCaseWarning]:
    """The texture against the finest GSD (m/px): texels coarser than it, and texels
    finer than a third of it (:func:`aliasing_warning`, as the plan report says it)."""
    if not math.isfinite(gsd_min_m):
        return []
    aliasing = aliasing_warning(project.scene.texture.source, gsd_min_m)
    out = [HardCaseWarning("texture", aliasing, "see docs/hard-cases.md")] if aliasing else []
    source = project.scene.texture.source
    if isinstance(source, m.ProceduralTexture) and source.texel_size_m > gsd_min_m:
        out.append(HardCaseWarning(
            "texture",
            f"the GSD ({100 * gsd_min_m:.2g} cm at its finest) is below the texture's texel "
            f"({100 * source.texel_size_m:.2g} cm): each texel spans "
            f"{source.texel_size_m / gsd_min_m:.3g} pixels, the ground shows interpolated "
            "texels whose grid repeats, and features match poorly",
            f"use a texel near GSD/2 ({100 * gsd_min_m / 2:.2g} cm) for this flight, or "
            "fly higher"))
    return out


def _coefficients(model) -> tuple[float, ...]:
    from designer.core.distortion import BrownConrady

    if isinstance(model, BrownConrady):
        return (model.k1, model.k2, model.k3)
    return (model.k1, model.k2, model.k3, model.k4)


def _radial_value(model, t: float) -> float:
    """g(t) = t·(1 + k1 t² + k2 t⁴ + …): the distorted radius (Brown: of undistorted radius
    t; fisheye: of the angle t off axis)."""
    return t * (1.0 + sum(k * t ** (2 * i + 2) for i, k in enumerate(_coefficients(model))))


def _radial_slope(model, t: float) -> float:
    """g'(t), the radial map's slope."""
    return 1.0 + sum((2 * i + 3) * k * t ** (2 * i + 2)
                     for i, k in enumerate(_coefficients(model)))


def distortion_warning(camera: m.Camera, resolution_scale: float = 1.0
                       ) -> HardCaseWarning | None:
    """A warning when the image corners come close to where the lens's radial map stops
    being monotonic: undistortion there magnifies radial pixel errors by 1/g'(t) ≥
    :data:`DISTORTION_WARN_MAGNIFICATION` (t: the corner's undistorted radius, or its
    angle off axis for a fisheye). Beyond that radius the camera is refused
    (designer.project.validate_camera)."""
    from designer.core.distortion import BrownConrady
    from designer.errors import NotInvertibleError
    from designer.project.interiors import render_interior

    io = render_interior(camera, resolution_scale)
    model = io.distortion
    if model is None or (isinstance(model, BrownConrady) and model.is_identity):
        return None
    W, H = io.image_size_px
    corners = np.array([[0.0, 0.0], [W, 0.0], [0.0, H], [W, H]])
    xd = (corners - [io.cx_px, io.cy_px]) / [io.fx_px, io.fy_px]
    far = xd[np.argmax(np.hypot(xd[:, 0], xd[:, 1]))][None]
    try:
        if isinstance(model, BrownConrady):
            t = float(np.hypot(*model.undistort(far)[0]))
            limit, tag = model.max_monotone_radius(), "brown-conrady"
        else:
            t = float(np.arccos(np.clip(model.rays_from_distorted(far)[0, 2], -1.0, 1.0)))
            limit, tag = min(model.max_monotone_theta(), math.pi), "fisheye-equidistant"
    except NotInvertibleError:
        return None  # beyond the lens map: the camera check refuses it
    slope = _radial_slope(model, t)
    magnification = math.inf if slope <= 0 else 1.0 / slope
    if magnification < DISTORTION_WARN_MAGNIFICATION:
        return None
    f_px = io.fx_px
    edge = (f" ({f_px * _radial_value(model, limit):.0f} px)" if math.isfinite(limit)
            else "")
    return HardCaseWarning(
        tag,
        f"camera {camera.id!r}: the image corner {f_px * float(np.hypot(*far[0])):.0f} px "
        f"from the principal point lies close to the radius where the lens map stops being "
        f"monotonic{edge}: undistorting pixels there magnifies their radial error "
        f"{magnification:.3g}x",
        "reduce the distortion coefficients or the image size/field of view, or crop the "
        "corners")


#: a pinhole camera wider than this across its image diagonal (deg) is wider than any
#: survey camera: the widest rectilinear lenses made (12 mm on full frame) see 122°, survey
#: cameras 60–95° (the Phantom 4 Pro 84°, the GoPro as a pinhole 104°), and at 120° the
#: ground under the corners is already seen 4× as coarse as under the centre (1/cos² 60°)
MAX_PINHOLE_FOV_DEG = 120.0
#: a flight whose GSD at nadir (m) is coarser than this is coarser than any survey flies:
#: the coarsest mapping flights give 50 cm (designer's own hard cases go there); at 1 m a
#: GCP target (0.5–1 m across) is a pixel or less and cannot be measured
MAX_SURVEY_GSD_M = 1.0
#: what the focal length is, as the fixes say it
_REAL_FOCAL = "the lens's real focal length in mm, not its 35 mm equivalent"


def wide_lens_warning(camera: m.Camera) -> HardCaseWarning | None:
    """A pinhole camera (no fisheye model) wider than :data:`MAX_PINHOLE_FOV_DEG` across
    its diagonal, measured through its lens (designer.core.interior.field_of_view_deg, as
    the window's Camera panel shows it); None for a fisheye or a camera no interior
    orientation describes (the camera check says why)."""
    from designer.project.interiors import interior_from_camera

    if isinstance(camera.distortion, m.FisheyeEquidistantDistortion):
        return None
    try:
        h, v, diag = interior_from_camera(camera).field_of_view_deg()
    except DesignerError:
        return None
    if not diag > MAX_PINHOLE_FOV_DEG:
        return None
    return HardCaseWarning(
        "camera",
        f"camera '{camera.id}': a {camera.focal_length_mm:g} mm lens on a "
        f"{camera.sensor_width_mm:g} × {camera.sensor_height_mm:g} mm sensor sees "
        f"{diag:.0f}° across the diagonal ({h:.0f}° × {v:.0f}°), wider than any survey "
        f"camera's (at most {MAX_PINHOLE_FOV_DEG:g}° for a pinhole lens): the ground under "
        "the image corners is seen far coarser than under the centre, and a focal length "
        "in the wrong unit looks like this",
        f"check the focal length (focal-length-mm: {_REAL_FOCAL})",
        f"check the focal length in the Camera panel ({_REAL_FOCAL})")


def coarse_gsd_warning(project: m.Project) -> HardCaseWarning | None:
    """The flight plan's GSD at nadir (its camera's full-size images, as the Camera
    panel's figure) coarser than :data:`MAX_SURVEY_GSD_M`; None without a flight plan or
    for a camera no interior orientation describes."""
    from designer.project.interiors import interior_from_camera
    from designer.survey.flight import camera_calc
    from designer.survey.project_poses import planning_camera_id

    plan = project.trajectory.flight_plan
    if plan is None:
        return None
    try:
        camera_id = planning_camera_id(project, plan.camera)
        calc = camera_calc(interior_from_camera(project.camera(camera_id)),
                           altitude_agl_m=plan.altitude_agl_m, gsd_m=plan.gsd_m,
                           front_overlap_fraction=plan.front_overlap_percent / 100,
                           side_overlap_fraction=plan.side_overlap_percent / 100,
                           orientation=plan.orientation)
    except (DesignerError, KeyError, ValueError):
        return None
    if not calc.gsd_m > MAX_SURVEY_GSD_M:
        return None
    by = ("fly lower (altitude-agl-m)" if plan.gsd_m is None else "choose a finer gsd-m")
    panel = ("lower the height above ground in the Flight panel" if plan.gsd_m is None
             else "choose a finer ground sample distance in the Flight panel")
    return HardCaseWarning(
        "flight-plan",
        f"the flight's GSD is {100 * calc.gsd_m:,.0f} cm ({calc.altitude_agl_m:g} m above "
        f"the ground with camera '{camera_id}'), coarser than any survey flies (at most "
        f"{100 * MAX_SURVEY_GSD_M:g} cm): a GCP target is smaller than a pixel",
        f"check the camera's focal length and sensor ({_REAL_FOCAL}), or {by}",
        f"check the focal length and sensor in the Camera panel ({_REAL_FOCAL}), or {panel}")


def optics_warnings(project: m.Project) -> list[HardCaseWarning]:
    """Cameras wider and a flight coarser than any survey's (:func:`wide_lens_warning`,
    :func:`coarse_gsd_warning`): from the declarations alone, microseconds."""
    out = [w for cam in project.cameras if (w := wide_lens_warning(cam)) is not None]
    gsd = coarse_gsd_warning(project)
    return out + ([gsd] if gsd is not None else [])


#: front overlap (%) below which consecutive images share less than half their footprint:
#: few ground points are then seen by the 3 images a tie point needs along a line
MIN_FRONT_OVERLAP_PERCENT = 50.0


def network_warnings(project: m.Project, n_images: int, line_indices) -> list[HardCaseWarning]:
    """The image network against what SfM needs: ``n_images`` images taken at platform
    stations on the flight lines ``line_indices`` (negative: lines of explicit photos)."""
    out = []
    if n_images < 3:
        out.append(HardCaseWarning(
            "trajectory", f"{n_images} image{'s' if n_images != 1 else ''}: structure from "
            "motion needs at least 3 overlapping images (designer reconstruct refuses fewer)",
            "add photos, or fly a flight plan over the area",
            "add photos, or draw a flight area in the Flight panel"))
    lines = {int(k) for k in line_indices}
    if n_images >= 3 and len(lines) == 1 and min(lines) >= 0:
        out.append(HardCaseWarning(
            "flight-plan", f"all {n_images} images lie on one flight line: no side overlap, "
            "the block rests on one strip and control along it is nearly collinear (its roll "
            "about the line is weakly determined)",
            "fly a second line (widen the area or raise side-overlap-percent), or place "
            "control on both sides of the line",
            "fly a second line (widen the area or raise the side overlap in the Flight "
            "panel), or place control on both sides of the line"))
    plan = project.trajectory.flight_plan
    if plan is not None and plan.front_overlap_percent < MIN_FRONT_OVERLAP_PERCENT:
        out.append(HardCaseWarning(
            "flight-plan", f"front overlap {plan.front_overlap_percent:g} %: consecutive "
            "images share less than half their footprint, so few ground points are seen by "
            "the 3 images a tie point needs",
            "raise front-overlap-percent to 60 or more",
            "raise the front overlap in the Flight panel to 60 % or more"))
    return out


def control_and_network_warnings(project: m.Project, base_dir: Path
                                 ) -> list[HardCaseWarning]:
    """The warnings of this module that need no height field, in :func:`hard_case_warnings`'
    words: nearly collinear control (its surveyed coordinates) and a network too thin for
    SfM (its images and lines), on a terrain mesh as on a height field."""
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_images

    try:
        hf = build_heightfield(project.scene.terrain, Path(base_dir), project.crs)
    except DesignerError:  # the terrain cannot be built: check says why elsewhere
        return []
    try:
        images = project_images(project, hf)
    except DesignerError:  # the flight cannot be planned: check says why elsewhere
        images = None
    return _control_and_network(project, hf, images)


def _control_and_network(project: m.Project, hf, images) -> list[HardCaseWarning]:
    """Collinear control over ``hf`` (None: a terrain mesh) and the network of
    ``images`` (project_images; None: none planned)."""
    from designer.scene.build import build_targets

    try:
        warning = control_warning(build_targets(project, hf))
    except DesignerError:  # the targets cannot be built: check says why elsewhere
        return []
    out = [warning] if warning is not None else []
    if images is not None:
        out += network_warnings(project, len(images.stations),
                                [images.platform[k].line_index for k in images.station_index])
    return out


def hard_case_warnings(project: m.Project, base_dir: Path) -> list[HardCaseWarning]:
    """Every warning of this module for ``project`` (files relative to ``base_dir``).

    On a terrain mesh the lenses, the control's spread (its surveyed coordinates) and the
    network (its images and lines) are weighed as on a height field; the texture against
    the finest GSD is not: the GSD is measured by casting rays on a height field."""
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_images

    out = [w for cam in project.cameras
           if (w := distortion_warning(cam, project.render.resolution_scale)) is not None]
    out += optics_warnings(project)
    try:
        hf = build_heightfield(project.scene.terrain, Path(base_dir), project.crs)
    except DesignerError:  # the terrain cannot be built: check says why elsewhere
        return out
    try:
        images = project_images(project, hf)
    except DesignerError:  # the flight cannot be planned: check says why elsewhere
        images = None
    out += _control_and_network(project, hf, images)
    if hf is not None and images is not None and len(images.stations):
        out += texture_warnings(project, finest_gsd_m(project, hf, images))
    return out
