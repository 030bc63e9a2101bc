"""Cameras and tie points from the matches (pycolmap): triangulation with the true poses
(``known-poses``), or structure from motion (``free``) by COLMAP's incremental mapper or
GLOMAP's global one, a project's rigs written into the database first (designer.sfm.rigs).
With a feature cache the SfM model is taken from a run with the same matches, interior
refinement, mapper and rig layout. Local frame, metres.
"""

from __future__ import annotations

import contextlib
import copy
import shutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from designer.errors import DesignerError
from designer.project import model as m
from designer.sfm.feature_cache import FeatureCache
from designer.sfm.feature_cache import key as fc_key
from designer.sfm.features import Features, Matches
from designer.sfm.inputs import SurveyCamera, SurveyInputs


@dataclass(frozen=True)
class Mapped:
    """The reconstruction (pycolmap, local frame) and, in ``free`` mode, whether its SfM
    model was taken from the feature cache (None in ``known-poses``)."""

    rec: object
    reused: bool | None


def map_cameras(inputs: SurveyInputs, features: Features, matches: Matches, layout,
                sparse: Path, cache: FeatureCache | None, log: Callable[[str], None]) -> Mapped:
    """The tie points triangulated with the true poses (``known-poses``) or the cameras
    and tie points found by the settings' mapper (``free``; ``layout``: the rigs written
    into the database, or None), working in a new ``sparse`` folder; a clear error when
    a camera of several has no image in the model."""
    import pycolmap

    if sparse.exists():
        shutil.rmtree(sparse)
    sparse.mkdir()
    db_path, image_dir = features.db_path, inputs.image_dir
    if inputs.mode == "known-poses":
        log("triangulating with the true poses")
        rec = known_pose_reconstruction(pycolmap, inputs.truth, db_path)
        return Mapped(pycolmap.triangulate_points(rec, db_path, image_dir, sparse), None)
    p = inputs.processing
    # the mapper's model depends on the matches, the interior it refines, the mapper
    # and the rig layout: runs that differ only after SfM share it
    # (the incremental mapper's adjustment growth only when not COLMAP's default, so
    # models kept before the setting existed are still found)
    growth = p.sfm.global_adjustment_growth
    growth_key = () if p.sfm.mapper == "global" or growth == DEFAULT_GROWTH else (growth,)
    sfm_key = fc_key("sfm", matches.key, p.calibration.mode, p.sfm.mapper,
                     repr(None if layout is None else sorted(layout.frames.items())),
                     *growth_key) if cache else ""
    with cache.hold("sfm", sfm_key) if cache else contextlib.nullcontext():
        reused = bool(cache) and cache.fetch_model(sfm_key, sparse / "cached")
        if reused:
            log("SfM model reused from the feature cache")
            rec = pycolmap.Reconstruction(str(sparse / "cached"))
        elif p.sfm.mapper == "global":
            log("global SfM (rotation averaging, global positioning)")
            rec = global_sfm(pycolmap, db_path, image_dir, sparse, p.calibration.mode)
        else:
            log("incremental SfM")
            rec = incremental_sfm(pycolmap, db_path, image_dir, sparse, p.calibration.mode,
                                  global_ba_ratio=growth)
        if cache and not reused:
            cache.store_model(sfm_key, rec)
    check_every_camera_registered(rec, inputs.cams, inputs.survey)
    return Mapped(rec, reused)


def tied_images(rec) -> set[str]:
    """The names of the registered images that observe a tie point. An image of a rig
    has a pose as soon as its station is registered; it counts only when its own features
    joined the reconstruction."""
    return {img.name for img in rec.images.values()
            if img.has_pose and img.num_points3D > 0}


def apply_rigs(db_path: Path, cams: list[SurveyCamera], rigs, project_path,
               survey: Path, log: Callable[[str], None]):
    """The rigs (designer.sfm.rigs.ProcessingRig; None: the project's, when it is found)
    written into the database, as designer.sfm.rigs.apply_rigs lays them out, or None."""
    import pycolmap

    from designer.sfm import rigs as rig_model

    if rigs is None:
        from designer.project.load import load_project
        from designer.sfm.settings import project_of_survey

        path = project_path or project_of_survey(survey)
        if path is None:
            if len(cams) > 1:
                log("the project is not found: a rig's images are each posed alone")
            return None
        rigs = rig_model.processing_rigs(load_project(path, check_files=False))
    if not rigs:
        return None
    # a one-camera survey's ground truth does not name its camera: its images match a
    # mount by suffix alone
    named = {c.label for c in cams} & {s.camera_label for r in rigs for s in r.sensors}
    layout = rig_model.apply_rigs(pycolmap, db_path, rigs,
                                  {n: c.label if named else None for c in cams for n in c.names})
    for name, frames in layout.frames.items():
        log(f"rig {name}: {len(frames)} stations, the mounts' relative orientation fixed")
    return layout


def check_every_camera_registered(rec, cams: list[SurveyCamera], survey: Path) -> None:
    """A camera none of whose images joined the reconstruction (a rig whose cameras see
    nothing in common) is a clear error, not a survey of the other cameras."""
    if len(cams) == 1:
        return
    registered = tied_images(rec)
    lost = [c for c in cams if not registered.intersection(c.names)]
    if lost:
        what = ", ".join(f"{c.label!r} ({len(c.names)} images)" for c in lost)
        raise DesignerError(
            f"{survey}: no image of camera {what} registered with the other cameras' "
            "images: the rig's cameras see nothing in common; fly the rig so that each "
            "camera's footprints overlap another camera's (tilt the obliques less, raise the "
            "overlaps) or process each camera's images as a survey of their own")


#: COLMAP's growth of the model between two adjustments of the whole model (the
#: project's default, <sfm global-adjustment-growth>)
DEFAULT_GROWTH = m.Sfm().global_adjustment_growth


def incremental_sfm(pycolmap, db_path, image_dir, sparse, calibration: str,
                    global_ba_ratio: float = DEFAULT_GROWTH):
    """COLMAP's incremental mapper, seeded, set for survey images; its largest model.
    ``global_ba_ratio``: the growth of the model (registered images, tie points) between
    two adjustments of the whole model (COLMAP's default 1.1; ``<sfm
    global-adjustment-growth>``; designer bench mapper measures others)."""
    options = pycolmap.IncrementalPipelineOptions()
    options.ba_global_frames_ratio = options.ba_global_points_ratio = global_ba_ratio
    options.num_threads = -1
    options.random_seed = 0  # RANSAC and the mapper's choices seeded: runs repeat closer
    options.ba_refine_sensor_from_rig = False  # a rig's calibration is known (designer.sfm.rigs)
    # Nadir survey images have small baselines: the default 16° initial triangulation
    # angle rejects every pair of a typical 80 % overlap flight.
    options.mapper.init_min_tri_angle = 4.0
    options.mapper.init_min_num_inliers = 50
    (options.ba_refine_focal_length, options.ba_refine_principal_point,
     options.ba_refine_extra_params) = mapper_refines(calibration)
    maps = pycolmap.incremental_mapping(db_path, image_dir, sparse, options=options)
    return largest_model(maps, image_dir, "COLMAP could not start a reconstruction")


def largest_model(maps: dict, image_dir, failure: str):
    """The model of ``maps`` (a mapper's models by index) with the most registered images;
    none is a DesignerError naming ``image_dir`` and the mapper's ``failure``."""
    if not maps:
        raise DesignerError(f"{image_dir}: {failure}: the images do not overlap enough or "
                            "show too little texture")
    return max(maps.values(), key=lambda r: r.num_reg_images())


def mapper_refines(calibration: str) -> tuple[bool, bool, bool]:
    """(focal length, principal point, distortion) the mapper's own adjustments refine
    for the calibration mode: at most the focal length (COLMAP's own default); the
    principal point and distortion are estimated in the final adjustment, with exactly
    the mode's terms. A principal point refined while a flat block grows drifts with the
    few images registered so far, and the next images then fail to register."""
    return calibration != "fixed", False, False


def global_sfm(pycolmap, db_path, image_dir, sparse, calibration: str):
    """GLOMAP's global SfM (pycolmap.global_mapping): rotation averaging, global
    positioning, one bundle adjustment, refining the interior as the incremental mapper
    does (distortion in the final adjustment, with exactly the mode's terms)."""
    options = pycolmap.GlobalPipelineOptions()
    options.num_threads = -1
    options.random_seed = 0  # the same images give the same model
    ba = options.mapper.bundle_adjustment
    ba.refine_focal_length, ba.refine_principal_point, ba.refine_extra_params = \
        mapper_refines(calibration)
    ba.refine_sensor_from_rig = False  # a rig's calibration is known (designer.sfm.rigs)
    maps = pycolmap.global_mapping(db_path, image_dir, sparse, options=options)
    return largest_model(maps, image_dir, "COLMAP's global mapper found no reconstruction")


def known_pose_reconstruction(pycolmap, truth, db_path: Path):
    """The true model for the images in the database, with the database's ids."""
    rec = pycolmap.Reconstruction()
    db = pycolmap.Database.open(str(db_path))
    try:
        images = sorted(db.read_all_images(), key=lambda i: i.image_id)
        for camera_id in sorted(c.camera_id for c in db.read_all_cameras()):
            # the true camera of the database camera's first image (a rig: each its own)
            first = next((i for i in images if i.camera_id == camera_id), None)
            src = truth.cameras[truth.find_image_with_name(first.name).camera_id] \
                if first is not None else next(iter(truth.cameras.values()))
            true_camera = copy.copy(src)  # the truth keeps its ids
            true_camera.camera_id = camera_id
            rec.add_camera_with_trivial_rig(true_camera)
        for db_image in images:
            src = truth.find_image_with_name(db_image.name)
            image = pycolmap.Image(name=db_image.name, camera_id=db_image.camera_id,
                                   image_id=db_image.image_id)
            rec.add_image_with_trivial_frame(image, src.cam_from_world())
    finally:
        db.close()
    return rec
