"""Real survey cameras as presets: sensor (mm), image (px), focal length (mm).

Sources: manufacturers' specifications as gathered in the project's background notes
(``formats-and-cameras``); every focal length is the real one, not the 35 mm
equivalent (checked through the pixel pitch and the field of view).

Square pixels: designer rejects a camera whose pixel pitch across (sw/W) and along
(sh/H) differ by more than 1e-6 relative. Published sensor heights are rounded, so for
the cameras where sw/W and sh/H disagree (a6000 0.4 %, ILCE-QX1 0.3 %, GoPro Hero 4
1.7 %, Sequoia 0.05 %, GR II 0.01 %, Mavic 3E 0.3 %) the preset keeps the published
sensor **width** and sets the height to ``sw · H / W`` exactly. The Zenmuse P1 is given
by its 4.4 µm pixel pitch (36.0448 × 24.024 mm). Distortion is left at zero: the presets
describe the interior geometry, not a calibrated lens. The GoPro is a fisheye in
reality; here it is the pinhole of its published focal length.

``exif_models`` are the EXIF ``Model`` strings the camera writes into its images (DJI
writes the camera's name, e.g. FC6310 for the Phantom 4 Pro, FC6310S for its V2.0,
ZenmuseP1, M3E); the flight importer (:mod:`designer.flight.camera_pick`) names a preset
by them and confirms it by focal length and image size.
"""

from __future__ import annotations

from dataclasses import dataclass

from designer.project import model as m


@dataclass(frozen=True)
class CameraPreset:
    key: str
    name: str
    focal_length_mm: float
    sensor_width_mm: float
    published_sensor_height_mm: float
    image_width_px: int
    image_height_px: int
    #: EXIF Model strings of images taken with this camera (compared case-insensitively)
    exif_models: tuple[str, ...] = ()

    @property
    def sensor_height_mm(self) -> float:
        """Sensor height that makes the pixels square: sw · H / W."""
        return self.sensor_width_mm * self.image_height_px / self.image_width_px

    @property
    def pixel_pitch_um(self) -> float:
        return 1000.0 * self.sensor_width_mm / self.image_width_px

    def camera(self, camera_id: str | None = None) -> m.Camera:
        """The preset as a project camera (pinhole, centred principal point)."""
        return m.Camera(
            id=camera_id or self.key, name=self.name, focal_length_mm=self.focal_length_mm,
            sensor_width_mm=self.sensor_width_mm, sensor_height_mm=self.sensor_height_mm,
            image_width_px=self.image_width_px, image_height_px=self.image_height_px)


PRESETS: tuple[CameraPreset, ...] = (
    CameraPreset("p4p", "DJI Phantom 4 Pro (1-inch, 20 MP)", 8.8, 13.2, 8.8, 5472, 3648,
                 exif_models=("FC6310", "FC6310S", "FC6310R")),
    CameraPreset("rx100m2", "Sony RX100 II", 10.4, 13.2, 8.8, 5472, 3648,
                 exif_models=("DSC-RX100M2",)),
    CameraPreset("a6000", "Sony a6000, 16 mm", 16.0, 23.5, 15.6, 6000, 4000,
                 exif_models=("ILCE-6000",)),
    CameraPreset("a7r4", "Sony a7R IV, 35 mm", 35.0, 35.7, 23.8, 9504, 6336,
                 exif_models=("ILCE-7RM4",)),
    CameraPreset("qx1", "Sony ILCE-QX1, 16 mm", 16.0, 23.2, 15.4, 5456, 3632,
                 exif_models=("ILCE-QX1",)),
    CameraPreset("s100", "Canon PowerShot S100", 5.2, 7.6, 5.7, 4000, 3000,
                 exif_models=("Canon PowerShot S100",)),
    CameraPreset("gopro4", "GoPro Hero 4 (as a pinhole)", 2.98, 6.17, 4.55, 4000, 3000,
                 exif_models=("HERO4 Black", "HERO4 Silver")),
    CameraPreset("sequoia", "Parrot Sequoia RGB", 4.9, 6.17, 4.63, 4608, 3456,
                 exif_models=("Sequoia",)),
    CameraPreset("gr2", "Ricoh GR II", 18.3, 23.7, 15.7, 4928, 3264,
                 exif_models=("GR II",)),
    CameraPreset("p1", "DJI Zenmuse P1, 35 mm (4.4 µm pixels)", 35.0, 8192 * 0.0044,
                 5460 * 0.0044, 8192, 5460,
                 exif_models=("ZenmuseP1",)),
    CameraPreset("m3e", "DJI Mavic 3E wide", 12.29, 17.3, 13.0, 5280, 3956,
                 exif_models=("M3E",)),
)


def preset(key: str) -> CameraPreset:
    for p in PRESETS:
        if p.key == key:
            return p
    raise KeyError(key)


def matching_preset(camera: m.Camera) -> CameraPreset | None:
    """The preset whose geometry equals this camera's (to 1e-9 mm), if any."""
    for p in PRESETS:
        if (abs(p.focal_length_mm - camera.focal_length_mm) < 1e-9
                and abs(p.sensor_width_mm - camera.sensor_width_mm) < 1e-9
                and abs(p.sensor_height_mm - camera.sensor_height_mm) < 1e-9
                and (p.image_width_px, p.image_height_px)
                == (camera.image_width_px, camera.image_height_px)):
            return p
    return None
