"""Multi-camera rigs in processing: the project's rigs as COLMAP rigs and frames.

A rig's images are grouped into frames by station (the image name with the mount's
suffix removed, designer.core.rig). Each mount is a sensor with its own database camera —
its own interior orientation, as each camera of a multi-camera system is calibrated on
its own — so a project camera used by several mounts (four obliques) becomes one database
camera per mount. The first mount is the reference sensor; every other mount's
cam_from_rig is the project's mount rotation relative to it, with no translation (all
mounts share the station's perspective centre). The mapper and the adjustments keep
cam_from_rig fixed (the rig's calibration is known), so a station has one pose,
rig_from_world, shared by its images.

Frames (docs/conventions.md): R_cam_to_world = R_platform · R_mount in photogrammetric
axes (x right, y image top, z backwards); COLMAP's camera frame is the computer-vision
one, R_cam_from_world = R_CV_FROM_PHOTO · R_cam_to_worldᵀ. Hence

    R_cam_from_rig = R_CV_FROM_PHOTO · R_mountᵀ · R_ref_mount · R_CV_FROM_PHOTO.
"""

from __future__ import annotations

import posixpath
from dataclasses import dataclass

import numpy as np

from designer.core.rig import mount_rotation
from designer.core.rotation import R_CV_FROM_PHOTO
from designer.project import model as m


@dataclass(frozen=True)
class RigSensor:
    """One mount of a rig in processing: its image-name suffix, the project camera it
    carries and its rotation cam_from_rig (3, 3; COLMAP camera axes; reference: identity)."""

    suffix: str
    camera_label: str
    R_cam_from_rig: np.ndarray

    @property
    def label(self) -> str:
        """How reports name the sensor: the camera and the mount's suffix (``oblique _F``)."""
        return f"{self.camera_label} {self.suffix}"


@dataclass(frozen=True)
class ProcessingRig:
    """A project rig: its name and sensors, the reference (first mount) first."""

    name: str
    sensors: tuple[RigSensor, ...]


@dataclass(frozen=True)
class RigLayout:
    """What :func:`apply_rigs` wrote: the frames of each rig (station → {suffix: image
    name}) and, by image name, the label of the sensor that took it (rig images only)."""

    frames: dict[str, dict[str, dict[str, str]]]
    sensor_of: dict[str, str]

    @property
    def stations(self) -> int:
        return sum(len(f) for f in self.frames.values())


def processing_rigs(project: m.Project) -> list[ProcessingRig]:
    """The project's rigs with two or more mounts, as processing sees them."""
    rigs = []
    for rig in project.trajectory.rigs:
        if len(rig.mounts) < 2:
            continue
        ref = mount_rotation(rig.mounts[0].omega_deg, rig.mounts[0].phi_deg,
                             rig.mounts[0].kappa_deg)
        rigs.append(ProcessingRig(rig.name, tuple(
            RigSensor(mt.suffix, mt.camera,
                      cam_from_rig(mount_rotation(mt.omega_deg, mt.phi_deg, mt.kappa_deg), ref))
            for mt in rig.mounts)))
    return rigs


def cam_from_rig(R_mount: np.ndarray, R_ref_mount: np.ndarray) -> np.ndarray:
    """R_cam_from_rig (3, 3) of a mount relative to the reference mount (module doc)."""
    return R_CV_FROM_PHOTO @ np.asarray(R_mount, float).T @ np.asarray(R_ref_mount, float) \
        @ R_CV_FROM_PHOTO


def station_of(image_name: str, suffix: str) -> str | None:
    """The station's image name of a mount's image (IMG_00001_F.png, _F → IMG_00001.png),
    or None when the name does not end in the suffix."""
    stem, ext = posixpath.splitext(image_name)
    if not suffix or not stem.endswith(suffix) or len(stem) == len(suffix):
        return None
    return stem[: -len(suffix)] + ext


def rig_frames(rig: ProcessingRig, names: list[str], camera_of: dict[str, str | None]
               ) -> dict[str, dict[str, str]]:
    """The stations of ``rig`` among ``names`` (image name → project camera id in
    ``camera_of``; None: not known, the suffix decides): station → {suffix: image name};
    only stations with two or more images."""
    frames: dict[str, dict[str, str]] = {}
    for name in names:
        for sensor in rig.sensors:
            station = station_of(name, sensor.suffix)
            if station is not None and camera_of.get(name) in (sensor.camera_label, None):
                frames.setdefault(station, {})[sensor.suffix] = name
                break
    return {s: f for s, f in sorted(frames.items()) if len(f) >= 2}


def apply_rigs(pycolmap, db_path, rigs: list[ProcessingRig],
               camera_of: dict[str, str | None]) -> RigLayout:
    """Write the rigs into the COLMAP database at ``db_path`` (after feature extraction):
    a database camera per mount, one rig per project rig, one frame per station; every
    other image keeps a rig and frame of its own. ``camera_of``: image name → project
    camera id. Returns what was written (no rig with two stations: nothing)."""
    import pycolmap as pc

    db = pycolmap.Database.open(str(db_path))
    try:
        images = {img.name: img for img in db.read_all_images()}
        cameras = {c.camera_id: c for c in db.read_all_cameras()}
        layout = RigLayout({}, {})
        taken: dict[int, str] = {}  # database camera id → the sensor label using it
        sensor_camera: dict[tuple[str, str], int] = {}  # (rig, suffix) → database camera id
        moved: dict[str, int] = {}  # image name → its mount's new database camera
        for rig in rigs:
            frames = rig_frames(rig, list(images), camera_of)
            if len(frames) < 2:
                continue
            layout.frames[rig.name] = frames
            for sensor in rig.sensors:
                own = [f[sensor.suffix] for f in frames.values() if sensor.suffix in f]
                if not own:
                    continue
                cid = images[own[0]].camera_id
                if cid in taken:  # the camera is another mount's: a camera of its own
                    cid = db.write_camera(pc.Camera(cameras[cid].todict()))
                    for name in own:
                        moved[name] = cid
                taken[cid] = sensor.label
                sensor_camera[(rig.name, sensor.suffix)] = cid
                for name in own:
                    layout.sensor_of[name] = sensor.label
        if not layout.frames:
            return layout
        db.clear_frames()  # an image changes camera only outside any frame
        db.clear_rigs()
        for name, cid in moved.items():
            db.update_image(pc.Image(name=name, camera_id=cid,
                                     image_id=images[name].image_id))
            images[name] = db.read_image(images[name].image_id)
        rig_of_camera: dict[int, int] = {}
        for rig in rigs:
            if rig.name not in layout.frames:
                continue
            colmap_rig = pc.Rig()
            present = [s for s in rig.sensors if (rig.name, s.suffix) in sensor_camera]
            for k, sensor in enumerate(present):
                sensor_id = pc.sensor_t(pc.SensorType.CAMERA,
                                        sensor_camera[(rig.name, sensor.suffix)])
                if k == 0:
                    colmap_rig.add_ref_sensor(sensor_id)
                else:  # relative to the first present mount (the reference if present)
                    R = sensor.R_cam_from_rig @ present[0].R_cam_from_rig.T
                    colmap_rig.add_sensor(sensor_id, pc.Rigid3d(pc.Rotation3d(R),
                                                                np.zeros(3)))
            rig_id = db.write_rig(colmap_rig)
            for sensor in present:
                rig_of_camera[sensor_camera[(rig.name, sensor.suffix)]] = rig_id
        for cid in sorted(cameras.keys() | set(sensor_camera.values())):
            if cid not in rig_of_camera:
                trivial = pc.Rig()
                trivial.add_ref_sensor(pc.sensor_t(pc.SensorType.CAMERA, cid))
                rig_of_camera[cid] = db.write_rig(trivial)
        in_frame = set()
        for rig in rigs:
            for station_images in layout.frames.get(rig.name, {}).values():
                _write_frame(pc, db, [images[n] for n in station_images.values()],
                             rig_of_camera)
                in_frame.update(station_images.values())
        for name, image in sorted(images.items()):
            if name not in in_frame:
                _write_frame(pc, db, [image], rig_of_camera)
        return layout
    finally:
        db.close()


def _write_frame(pc, db, images: list, rig_of_camera: dict[int, int]) -> None:
    frame = pc.Frame()
    frame.rig_id = rig_of_camera[images[0].camera_id]
    for image in images:
        frame.add_data_id(pc.data_t(pc.sensor_t(pc.SensorType.CAMERA, image.camera_id),
                                    image.image_id))
    db.write_frame(frame)
