"""The layout of a render output folder, stated once for every reader and writer.

::

    OUT/images/IMAGE_NAME…   only the images: nothing else is ever written there (partial
                             images live in OUT/.designer-job/partial/ and are renamed
                             into place when complete), so programs that read a whole
                             folder (COLMAP's feature extractor reads recursively) see
                             exactly the survey
    OUT/ground-truth/…       COLMAP, OpenDroneMap, Metashape, OPK and GCP tables
    OUT/manifest.json        versions, settings, per-image render seconds and inputs
    OUT/README.txt           which file each program takes
    OUT/.designer-job/       working files: the render job, scene files, logs, partials

Folders written before ``images/`` existed hold their images at OUT's top level (the
*old layout*); :func:`images_dir` still finds them there, and a render with
``--resume`` moves them into ``images/`` (:func:`move_old_layout_images`).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

#: a folder that holds a survey and its reconstruction side by side, as ``designer demo``
#: writes it: DIR/survey (the render output), DIR/reconstruction (``designer
#: reconstruct``'s folder) and DIR/accuracy (the comparison with the truth)
SIDE_BY_SIDE_SURVEY_DIR = "survey"
SIDE_BY_SIDE_RECONSTRUCTION_DIR = "reconstruction"
SIDE_BY_SIDE_ACCURACY_DIR = "accuracy"

IMAGES_DIR = "images"
GROUND_TRUTH_DIR = "ground-truth"
#: the rolling-shutter table of ground truth (one row per image: readout, direction, …)
ROLLING_SHUTTER_CSV = "rolling_shutter.csv"
MANIFEST = "manifest.json"
README = "README.txt"
JOB_DIR = ".designer-job"
#: inside JOB_DIR: images being rendered, renamed into IMAGES_DIR when complete
PARTIAL_DIR = "partial"
#: file suffixes designer writes images with (and recognises as images)
IMAGE_SUFFIXES = frozenset({".png", ".tif", ".tiff", ".jpg", ".jpeg"})


def is_image_file(path: Path) -> bool:
    """A visible file whose suffix is an image format's."""
    return (path.is_file() and path.suffix.lower() in IMAGE_SUFFIXES
            and not path.name.startswith("."))


def old_layout_images(out_dir: Path) -> list[Path]:
    """Image files at the top level of ``out_dir`` when it has no ``images/`` folder
    (a folder rendered before the images got their own folder); [] otherwise."""
    out_dir = Path(out_dir)
    if (out_dir / IMAGES_DIR).is_dir() or not out_dir.is_dir():
        return []
    return sorted(p for p in out_dir.iterdir() if is_image_file(p))


def uses_old_layout(out_dir: Path) -> bool:
    """True when ``out_dir`` holds its images at the top level (the old layout)."""
    return bool(old_layout_images(out_dir))


def images_dir(out_dir: Path) -> Path:
    """The folder holding the images of the output folder ``out_dir``.

    ``OUT/images`` — or ``OUT`` itself for a folder in the old layout, so outputs
    rendered before stay readable.
    """
    out_dir = Path(out_dir)
    return out_dir if uses_old_layout(out_dir) else out_dir / IMAGES_DIR


def partial_dir(out_dir: Path) -> Path:
    """Where images are written while they render (outside the images folder)."""
    return Path(out_dir) / JOB_DIR / PARTIAL_DIR


def move_old_layout_images(out_dir: Path, names: Iterable[str]) -> list[str]:
    """Move the images named ``names`` from OUT's top level into ``OUT/images``.

    Only the named files move (renames on one file system: nothing is copied); other
    files at the top level stay. Returns the names moved.
    """
    out_dir = Path(out_dir)
    if not uses_old_layout(out_dir):
        return []
    target = out_dir / IMAGES_DIR
    target.mkdir(parents=True, exist_ok=True)
    moved = []
    for name in names:
        try:  # another process rendering a slice of the folder may move it first
            os.replace(out_dir / name, target / name)
        except FileNotFoundError:
            continue
        moved.append(name)
    return moved
