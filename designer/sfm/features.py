"""Features and matches of a survey's images into a COLMAP database (pycolmap, CPU).

SIFT features per camera (one database camera each, with its start parameters), the
image pairs to match (exhaustive, by position or by predicted footprint;
designer.survey.pairs) and their matches. With a feature cache
(designer.sfm.feature_cache) both steps are taken from earlier runs of the same images,
cameras and settings, and kept for later ones: the keys below name exactly what the
result depends on.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.errors import DesignerError
from designer.sfm.feature_cache import FeatureCache, images_digest
from designer.sfm.feature_cache import key as fc_key
from designer.sfm.inputs import SurveyCamera, SurveyInputs
from designer.survey import pairs as matching

#: SIFT's first octave (COLMAP's SiftExtraction.first_octave) for each <matching
#: sift-scale>: -1 works on the image doubled in size, 0 on the image, 1 on its half
FIRST_OCTAVE = {"doubled": -1, "original": 0, "half": 1}


@dataclass(frozen=True)
class Features:
    """The database holding the features, the cache key they were kept under ("" without
    a cache) and whether they were taken from the cache."""

    db_path: Path
    key: str
    reused: bool


@dataclass(frozen=True)
class Matches:
    """The image pairs matched (in the database), their cache key ("" without a cache)
    and whether the matches were taken from the cache."""

    pairs: list[tuple[str, str]]
    key: str
    reused: bool


def extract_features(inputs: SurveyInputs, db_path: Path, cache: FeatureCache | None,
                     log: Callable[[str], None]) -> Features:
    """SIFT features of the present images into a new database at ``db_path``, one
    database camera per camera with its start parameters (the truth in ``known-poses``)."""
    import pycolmap

    db_path.unlink(missing_ok=True)
    cams, names = inputs.cams, inputs.names
    readers = [_reader(pycolmap, c, start, inputs.mode)
               for c, start in zip(cams, inputs.starts, strict=True)]
    reader = readers[0]
    max_features = inputs.processing.matching.max_features
    first_octave = FIRST_OCTAVE[inputs.processing.matching.sift_scale]
    camera_key = (reader.camera_model, reader.camera_params) if len(cams) == 1 else \
        ("rig", repr([(c.names, r.camera_model, r.camera_params)
                      for c, r in zip(cams, readers, strict=True)]))
    # the first octave joins the key only when it is not COLMAP's default, so features
    # kept before the setting existed are still found
    octave_key = () if first_octave == -1 else (("first_octave", first_octave),)
    feature_key = fc_key("features", images_digest(inputs.image_dir, names), *camera_key,
                         max_features, *octave_key) if cache else ""
    with cache.hold("features", feature_key) if cache else contextlib.nullcontext():
        reused = bool(cache) and cache.fetch("features", feature_key, db_path)
        if not reused:
            log(f"features: {len(names)} images")
            for c, r in zip(cams, readers, strict=True):  # one database camera per camera
                _extract(pycolmap, db_path, inputs.image_dir,
                         names if len(cams) == 1 else list(c.names), r, max_features,
                         first_octave)
            if cache:
                cache.store("features", feature_key, db_path)
    return Features(db_path, feature_key, reused)


def match_features(inputs: SurveyInputs, features: Features, out: Path,
                   cache: FeatureCache | None, log: Callable[[str], None]) -> Matches:
    """The image pairs chosen as the settings say (written to ``out/pairs.txt``) matched
    into the features' database; a clear error when no two images overlap."""
    import pycolmap

    kind = inputs.processing.matching.pairs
    K_size = {n: (start, c.size_px) for c, start in zip(inputs.cams, inputs.starts, strict=True)
              for n in c.names}
    pairs = image_pairs(kind, inputs.names, inputs.truth, inputs.flight_C, K_size,
                        inputs.gcps, inputs.offset)
    if not pairs:
        raise DesignerError(f"{inputs.survey}: no two images overlap (by their predicted "
                            "footprints); the images do not overlap enough for a "
                            "reconstruction")
    pairs_text = "".join(f"{a} {b}\n" for a, b in pairs)
    pairs_file = out / "pairs.txt"
    write_text_atomic(pairs_file, pairs_text)
    match_key = fc_key("matches", features.key, pairs_text) if cache else ""
    with cache.hold("matches", match_key) if cache else contextlib.nullcontext():
        reused = bool(cache) and cache.fetch("matches", match_key, features.db_path)
        if not reused:
            log(f"matching: {len(pairs)} image pairs ({kind})")
            _match(pycolmap, features.db_path, pairs_file)
            if cache:
                cache.store("matches", match_key, features.db_path)
    return Matches(pairs, match_key, reused)


def image_pairs(kind: str, names: list[str], truth, flight_C: dict, K_size: dict, gcps,
                offset: np.ndarray) -> list[tuple[str, str]]:
    """Image pairs to match (``kind``: exhaustive, position or footprint); ``flight_C``:
    image name → measured centre (local frame, m); ``K_size``: image name → (its
    camera's FULL_OPENCV start parameters, (W, H) px)."""
    C_local = np.array([flight_C[n] for n in names])
    if kind == "exhaustive":
        return matching.exhaustive_pairs(names)
    if kind == "position":
        return matching.neighbour_pairs(names, C_local)
    ground = (float(np.median([g.true_xyz[2] for g in gcps])) - offset[2] if gcps
              else float(np.min(C_local[:, 2])) - 50.0)
    feet = [matching.footprint_xy(C, truth.find_image_with_name(n).cam_from_world()
                                  .rotation.matrix(), tuple(K_size[n][0][:4]), K_size[n][1],
                                  ground)
            for n, C in zip(names, C_local, strict=True)]
    return matching.footprint_pairs(names, feet)


def _reader(pycolmap, camera: SurveyCamera, start: np.ndarray, mode: str):
    reader = pycolmap.ImageReaderOptions()
    if mode == "free":
        reader.camera_model = "FULL_OPENCV"
        reader.camera_params = ",".join(repr(float(v)) for v in start)
    else:  # the true camera, exactly as the ground truth states it
        reader.camera_model = camera.camera.model.name
        reader.camera_params = ",".join(repr(float(v)) for v in camera.camera.params)
    return reader


def _extract(pycolmap, db_path: Path, image_dir: Path, names: list[str], reader,
             max_features: int, first_octave: int) -> None:
    extraction = pycolmap.FeatureExtractionOptions()
    extraction.sift.max_num_features = max_features
    extraction.sift.first_octave = first_octave
    extraction.use_gpu = False
    pycolmap.extract_features(db_path, image_dir, image_names=names,
                              camera_mode=pycolmap.CameraMode.SINGLE, reader_options=reader,
                              extraction_options=extraction, device=pycolmap.Device.cpu)


def _match(pycolmap, db_path: Path, pairs_file: Path) -> None:
    pairing = pycolmap.ImportedPairingOptions()
    pairing.match_list_path = str(pairs_file)
    match_options = pycolmap.FeatureMatchingOptions()
    match_options.use_gpu = False
    pycolmap.match_image_pairs(db_path, matching_options=match_options,
                               pairing_options=pairing, device=pycolmap.Device.cpu)
