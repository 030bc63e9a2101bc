"""What a reconstruction starts from: a rendered survey's images, cameras and marks.

The survey folder (an output folder of ``designer render``) is checked and read; the
ground truth is moved to a local frame (world − offset, offset = the rounded mean camera
centre, so no UTM-sized numbers reach COLMAP); each camera gets its start parameters
(the truth in ``known-poses``, a pre-calibration with its own error in ``free``); the
control points are marked with the marking error and the flight's camera positions
measured with the position prior's error. Local frame, metres; pixels for marks.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.core.layout import GROUND_TRUTH_DIR, images_dir
from designer.errors import DesignerError
from designer.export.colmap_read import model_offset_world
from designer.export.tables import read_gcp_observations_csv, read_gcp_truth_csv
from designer.project import model as m
from designer.sfm.georeference import translation
from designer.sfm.settings import (
    control_ids,
    flight_positions,
    marked_observations,
    start_params,
)

MODES = ("known-poses", "free")


def check_survey_folder(survey: Path) -> tuple[Path, Path, list[str]]:
    """The ground-truth COLMAP folder, the images folder and the names of the images present
    of a rendered survey (an output folder of 'designer render', :mod:`designer.core.layout`;
    one in the old layout, images at its top level, too), or a clear error."""
    survey = Path(survey)
    gt = survey / GROUND_TRUTH_DIR / "colmap"
    if not (gt / "images.txt").is_file() or not (gt / "cameras.txt").is_file():
        raise DesignerError(
            f"{survey}: no ground truth (ground-truth/colmap/images.txt); give the output "
            "folder of 'designer render' with its colmap ground truth")
    names = []
    for line in (gt / "images.txt").read_text().splitlines():
        parts = line.split()
        if len(parts) >= 10 and not line.startswith("#") and parts[0].isdigit():
            names.append(parts[9])
    folder = images_dir(survey)
    present = [n for n in names if (folder / n).is_file()]
    if len(present) < 3:
        raise DesignerError(
            f"{folder}: {len(present)} of {len(names)} images are present; at least 3 "
            "overlapping images are needed (render them first, or finish with --resume)")
    return gt, folder, present


@dataclass(frozen=True)
class SurveyCamera:
    """One physical camera of a survey: its ground-truth CAMERA_ID, designer camera id
    (``label``), the true pycolmap camera, its FULL_OPENCV parameters, and the names of
    the present images it took."""

    truth_id: int
    label: str
    camera: object
    true_params: np.ndarray
    names: tuple[str, ...]

    @property
    def size_px(self) -> tuple[int, int]:
        return (int(self.camera.width), int(self.camera.height))


def survey_cameras(truth, names: list[str], gt_dir: Path) -> list[SurveyCamera]:
    """The cameras that took the present images, by ground-truth CAMERA_ID (each camera
    of a rig its own interior orientation), named as the ground truth's comment names
    them (``# designer cameras: 1 = nadir, 2 = oblique``)."""
    labels = _camera_labels(gt_dir / "cameras.txt")
    by_id: dict[int, list[str]] = {}
    for n in names:
        by_id.setdefault(int(truth.find_image_with_name(n).camera_id), []).append(n)
    return [SurveyCamera(cid, labels.get(cid, f"camera {cid}"), truth.cameras[cid],
                         full_opencv(truth.cameras[cid]), tuple(own))
            for cid, own in sorted(by_id.items())]


def _camera_labels(cameras_txt: Path) -> dict[int, str]:
    for line in cameras_txt.read_text().splitlines():
        if line.startswith("# designer cameras:"):
            pairs = (item.split("=", 1) for item in line.split(":", 1)[1].split(","))
            return {int(k): v.strip() for k, v in pairs if k.strip().isdigit()}
    return {}


def full_opencv(camera) -> np.ndarray:
    """A pycolmap camera's parameters in FULL_OPENCV order (pixels; zeros for the terms
    its model lacks)."""
    params = np.zeros(12)
    p = np.asarray(camera.params, float)
    name = camera.model.name
    if name == "PINHOLE":
        params[:4] = p
    elif name == "OPENCV":
        params[:8] = p
    elif name == "FULL_OPENCV":
        params[:] = p
    else:
        raise DesignerError(f"camera model {name}: processing supports pinhole and "
                            "Brown–Conrady cameras; use a brown-conrady distortion")
    return params


@dataclass(frozen=True)
class SurveyInputs:
    """A survey read for processing, in the local frame (world − ``offset``, metres).

    ``truth``: the ground-truth pycolmap reconstruction (local frame); ``starts``: each
    camera's FULL_OPENCV start parameters; ``marks``: the marked GCP observations;
    ``true_C`` / ``flight_C``: image name → true / measured camera centre; ``rolling``:
    the rolling-shutter images to compensate (name → shutter) or None."""

    survey: Path
    mode: str
    processing: m.Processing
    gt_dir: Path
    image_dir: Path
    names: list[str]
    truth: object
    offset: np.ndarray
    cams: list[SurveyCamera]
    starts: list[np.ndarray]
    gcps: list
    marks: list
    control: set[str]
    true_C: dict[str, np.ndarray]
    flight_C: dict[str, np.ndarray]
    rolling: dict | None


def read_inputs(survey: Path, mode: str, processing: m.Processing, max_features: int | None,
                log: Callable[[str], None]) -> SurveyInputs:
    """The survey folder checked and read for ``mode`` (:data:`MODES`) with the
    processing settings, ``max_features`` overriding theirs when given; a clear error
    for a folder that cannot be processed so."""
    import pycolmap

    if mode not in MODES:
        raise DesignerError(f"--mode {mode!r}: use one of {', '.join(MODES)}")
    survey = Path(survey)
    gt_dir, image_dir, names = check_survey_folder(survey)
    p = processing
    rolling = _rolling_shutter(survey, mode, p, names)
    if max_features is not None:
        p = dataclasses.replace(p, matching=dataclasses.replace(p.matching,
                                                                max_features=max_features))
    truth = pycolmap.Reconstruction(str(gt_dir))
    offset = _to_local_frame(truth, gt_dir)
    cams = survey_cameras(truth, names, gt_dir)
    # each camera its own pre-calibration error (the seed + its index: camera 1 as before)
    starts = [start_params(c.true_params, pre_error(p.calibration.pre_calibration_error, k))
              if mode == "free" else c.true_params for k, c in enumerate(cams)]
    if len(cams) > 1:
        log(f"{len(cams)} cameras: " + ", ".join(f"{c.label} ({len(c.names)} images)"
                                                 for c in cams))
    gcps, marks = gcp_inputs(survey, p)
    true_C = {n: truth.find_image_with_name(n).projection_center() for n in names}
    sh, sv = p.position_prior.sigmas_m if p.position_prior.mode != "none" else (2.5, 5.0)
    measured = flight_positions(np.array([true_C[n] for n in names]), sh, sv,
                                p.position_prior.seed)
    return SurveyInputs(survey, mode, p, gt_dir, image_dir, names, truth, offset, cams,
                        starts, gcps, marks, control_ids(gcps, p.gcps.control), true_C,
                        dict(zip(names, measured, strict=True)), rolling)


def _rolling_shutter(survey: Path, mode: str, p: m.Processing, names: list[str]) -> dict | None:
    """The rolling-shutter images to compensate (designer.sfm.rolling_adjustment), or None
    when the settings do not compensate."""
    if p.calibration.rolling_shutter != "compensate":
        return None
    from designer.sfm.rolling_adjustment import check_compensation, read_rolling_shutter_truth

    if mode != "free":
        raise DesignerError(f"--rolling-shutter compensate with --mode {mode}: the "
                            "compensation is part of the bundle adjustment; use --mode "
                            "free (or --rolling-shutter none)")
    rolling = read_rolling_shutter_truth(survey)
    check_compensation(rolling, names, survey)
    return rolling


def _to_local_frame(truth, gt_dir: Path) -> np.ndarray:
    """The local frame's offset (world, m), ``truth`` moved into it in place. The ground
    truth is world − written (offset.json; zeros for a world-frame model); the offset is
    the mean camera centre rounded to metres, as the render's default."""
    written = model_offset_world(gt_dir)
    offset = np.round(np.mean([img.projection_center() for img in truth.images.values()],
                              axis=0) + written)
    if np.any(offset != written):
        truth.transform(translation(written - offset))
    return offset


def pre_error(pre, index: int):
    """The pre-calibration error of the ``index``-th camera: its own draw (seed + index)."""
    if pre is None or index == 0:
        return pre
    return dataclasses.replace(pre, seed=pre.seed + index)


def gcp_inputs(survey: Path, p: m.Processing):
    """The survey's GCPs (truth, world frame) and their marked observations (the marking
    error of the settings drawn); empty without GCPs."""
    gt = survey / GROUND_TRUTH_DIR
    if not (gt / "gcp_truth.csv").is_file():
        return [], []
    gcps = read_gcp_truth_csv(gt / "gcp_truth.csv")
    observations = read_gcp_observations_csv(gt / "gcp_observations.csv")
    return gcps, marked_observations(observations, p.gcps.marking_sigma_px, p.gcps.seed)
