"""``ground-truth/colmap/database.db``: a COLMAP database holding the cameras and images
of the true model, with the IDs of cameras.txt and images.txt.

COLMAP's ``feature_extractor`` numbers the images it finds in the order its threads
finish, so with default settings its IMAGE_IDs need not be those of images.txt, and
``point_triangulator`` then stops ("Check failed: existing_image.Name() ==
image.second.Name()"). An image already in the database keeps its IMAGE_ID and camera:
the extractor only adds its features. So this database, given to the extractor,
makes the command sequence of OUT/README.txt work with COLMAP's default settings.

Schema: COLMAP 3.8's (``src/base/database.cc``; later versions upgrade it when they
open the file): ``cameras`` (camera_id, model as COLMAP's model id, width, height,
params as float64 bytes, prior_focal_length = 1: the focal length is known),
``images`` (image_id, name, camera_id, pose priors left empty) and the empty tables
the extractor and matchers fill. Camera model ids: COLMAP's ``camera_models.h``.
"""

from __future__ import annotations

import os
import sqlite3
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path
from designer.core.interior import InteriorOrientation
from designer.core.truth import CameraPose, CameraSet
from designer.export.colmap import (
    CAMERA_ID,
    colmap_camera_ids,
    colmap_camera_model,
    image_ids_by_name,
)

#: COLMAP's camera model ids (camera_models.h), for the models designer writes
MODEL_IDS = {"SIMPLE_PINHOLE": 0, "PINHOLE": 1, "SIMPLE_RADIAL": 2, "RADIAL": 3,
             "OPENCV": 4, "OPENCV_FISHEYE": 5, "FULL_OPENCV": 6}

SCHEMA = """
CREATE TABLE IF NOT EXISTS cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL,
    model INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT NULL, params BLOB,
    prior_focal_length INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL,
    name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, prior_qw REAL, prior_qx REAL,
    prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty REAL, prior_tz REAL,
    CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < 2147483647),
    FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));
CREATE TABLE IF NOT EXISTS keypoints (image_id INTEGER PRIMARY KEY NOT NULL,
    rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB,
    FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);
CREATE TABLE IF NOT EXISTS descriptors (image_id INTEGER PRIMARY KEY NOT NULL,
    rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB,
    FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);
CREATE TABLE IF NOT EXISTS matches (pair_id INTEGER PRIMARY KEY NOT NULL,
    rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB);
CREATE TABLE IF NOT EXISTS two_view_geometries (pair_id INTEGER PRIMARY KEY NOT NULL,
    rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, config INTEGER NOT NULL,
    F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB);
CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name);
"""


def write_colmap_database(path: str | os.PathLike, interior: InteriorOrientation | CameraSet,
                          poses: Sequence[CameraPose]) -> Path:
    """Write the database (atomically: a new file replaces any old one whole)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(interior, CameraSet):
        numbers = colmap_camera_ids(interior)
        cameras = [(k, interior.interiors[c]) for c, k in numbers.items()]
        camera_of = {p.image_name: numbers[interior.camera_of(p.image_name)] for p in poses}
    else:
        cameras = [(CAMERA_ID, interior)]
        camera_of = {p.image_name: CAMERA_ID for p in poses}
    ids = image_ids_by_name([p.image_name for p in poses])
    with atomic_path(path) as tmp:
        tmp.unlink()
        db = sqlite3.connect(tmp)
        try:
            db.executescript(SCHEMA)
            for k, camera in cameras:
                model, params = colmap_camera_model(camera)
                W, H = camera.image_size_px
                db.execute("INSERT INTO cameras VALUES (?, ?, ?, ?, ?, 1)",
                           (k, MODEL_IDS[model], W, H,
                            np.asarray(params, np.float64).tobytes()))
            for name in sorted(ids, key=ids.get):
                db.execute("INSERT INTO images (image_id, name, camera_id) VALUES (?, ?, ?)",
                           (ids[name], name, camera_of[name]))
            db.commit()
        finally:
            db.close()
    return path
