"""The camera presets the GUI offers; the data lives in :mod:`designer.project.camera_presets`
(Qt-free, so the flight importer uses the same list)."""

from designer.project.camera_presets import (  # noqa: F401  (the GUI's face of the presets)
    PRESETS,
    CameraPreset,
    matching_preset,
    preset,
)
