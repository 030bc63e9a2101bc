"""Reconstructions of the same images share features and matches through the cache."""

from __future__ import annotations

import shutil

import pytest

from designer.sfm.feature_cache import FeatureCache
from designer.sfm.inputs import check_survey_folder
from designer.sfm.reconstruct import reconstruct

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def _database_rows(db_path, table: str) -> int:
    import sqlite3

    with sqlite3.connect(db_path) as db:
        return db.execute(f"SELECT COUNT(*) FROM {table}").fetchone()[0]


@pytest.fixture(scope="module")
def first(survey, tmp_path_factory):
    """A first known-poses reconstruction of ``survey`` into an empty cache: its folder
    (``cache``, the run in ``a``) and its result. 2048 SIFT features an image: what the
    cache keeps and reuses, not the tie-point density, is under test."""
    folder = tmp_path_factory.mktemp("first")
    result = reconstruct(survey, folder / "a", mode="known-poses", max_features=2048,
                         feature_cache=folder / "cache")
    return folder, result


def test_a_second_reconstruction_of_the_same_images_reuses_features_and_matches(
        survey, first, tmp_path):
    folder, first = first
    cache = folder / "cache"
    second = reconstruct(survey, tmp_path / "b", mode="known-poses", max_features=2048,
                         feature_cache=cache)
    assert first.summary["reused_from_cache"] == {"features": False, "matches": False}
    assert second.summary["reused_from_cache"] == {"features": True, "matches": True}
    # the same database: the same keypoints and verified matches, the same points
    for table in ("keypoints", "two_view_geometries"):
        assert _database_rows(folder / "a" / "database.db", table) == \
            _database_rows(tmp_path / "b" / "database.db", table) > 0
    assert second.n_points == first.n_points
    assert len(list(cache.glob("features-*/database.db"))) == 1
    assert len(list(cache.glob("matches-*/database.db"))) == 1


def test_a_changed_image_misses_the_cache(survey, first, tmp_path):
    import cv2

    cache = tmp_path / "cache"  # a copy of the cache the first run filled
    shutil.copytree(first[0] / "cache", cache)
    changed = tmp_path / "survey"
    shutil.copytree(survey, changed)
    _, _, names = check_survey_folder(changed)
    image = next(changed.rglob(names[0]))
    pixels = cv2.imread(str(image), cv2.IMREAD_UNCHANGED)
    pixels[:8, :8] = 255 - pixels[:8, :8]  # another image: other features
    assert cv2.imwrite(str(image), pixels)
    result = reconstruct(changed, tmp_path / "b", mode="known-poses", max_features=2048,
                         feature_cache=cache)
    assert result.summary["reused_from_cache"] == {"features": False, "matches": False}
    assert len(list(cache.glob("features-*/database.db"))) == 2


def test_a_cache_entry_is_complete_or_absent(tmp_path):
    cache = FeatureCache(tmp_path / "c")
    db = tmp_path / "database.db"
    db.write_bytes(b"x" * 1000)
    assert not cache.fetch("features", "k", tmp_path / "copy.db")
    with cache.hold("features", "k"):
        cache.store("features", "k", db)
    assert cache.fetch("features", "k", tmp_path / "copy.db")
    assert (tmp_path / "copy.db").read_bytes() == db.read_bytes()
    assert not list((tmp_path / "c").rglob("*.part"))


def test_runs_that_differ_only_after_sfm_share_the_mappers_model(survey, tmp_path):
    """GCP mode and marking error act after structure from motion: the second run takes
    the first one's model and gets the result a run without the cache gets."""
    import numpy as np

    from designer.sfm.settings import resolve_processing

    cache = tmp_path / "cache"
    # 2048 SIFT features an image: what is shared, not the tie-point density, is under test
    similarity = resolve_processing(survey, gcps="similarity", max_features=2048)
    bundle = resolve_processing(survey, gcps="bundle", marking_sigma_px=0.3,
                                max_features=2048)
    first = reconstruct(survey, tmp_path / "a", mode="free", processing=similarity,
                        feature_cache=cache)
    second = reconstruct(survey, tmp_path / "b", mode="free", processing=bundle,
                         feature_cache=cache)
    alone = reconstruct(survey, tmp_path / "c", mode="free", processing=bundle)
    assert first.summary["reused_from_cache"]["sfm"] is False
    assert second.summary["reused_from_cache"] == {"features": True, "matches": True,
                                                   "sfm": True}
    assert len(list(cache.glob("sfm-*/model"))) == 1
    # sharing the model changes no result beyond what two runs of COLMAP's multi-threaded
    # mapper differ by (at most 1 % of the tie points; the GCPs to 1 mm)
    assert second.n_registered == alone.n_registered
    assert abs(second.n_points - alone.n_points) <= 0.01 * alone.n_points
    for a, b in zip(second.summary["gcps"], alone.summary["gcps"], strict=True):
        assert np.allclose([a["dx_m"], a["dy_m"], a["dz_m"]],
                           [b["dx_m"], b["dy_m"], b["dz_m"]], atol=1e-3), (a, b)
    # another mapper is another model
    other = reconstruct(survey, tmp_path / "d", mode="free", feature_cache=cache,
                        processing=resolve_processing(survey, gcps="similarity",
                                                      mapper="global", max_features=2048))
    assert other.summary["reused_from_cache"]["sfm"] is False
    # so is another growth between the incremental mapper's whole-model adjustments
    growth = reconstruct(survey, tmp_path / "e", mode="free", feature_cache=cache,
                         processing=resolve_processing(survey, gcps="similarity",
                                                       global_adjustment_growth=1.4,
                                                       max_features=2048))
    assert growth.summary["reused_from_cache"] == {"features": True, "matches": True,
                                                   "sfm": False}
    assert growth.n_registered == first.n_registered == first.n_images


def _keypoint_scales_px(db_path):
    """Every keypoint's scale (px): the square root of its affine shape's determinant."""
    import sqlite3

    import numpy as np

    with sqlite3.connect(db_path) as db:
        rows = db.execute("SELECT rows, cols, data FROM keypoints").fetchall()
    shapes = [np.frombuffer(data, np.float32).reshape(n, c) for n, c, data in rows if n]
    kp = np.concatenate(shapes)
    return np.sqrt(np.abs(kp[:, 2] * kp[:, 5] - kp[:, 3] * kp[:, 4]))


def test_sift_on_the_original_image_finds_no_sub_pixel_features_and_has_its_own_key(
        survey, first, tmp_path):
    """<matching sift-scale="original">: SIFT's first octave on the image itself (COLMAP's
    first_octave 0), not on the image doubled (the default, -1). Its finest features are
    then twice as coarse, and its features are kept under their own cache key."""
    from designer.project import model as m

    folder, doubled = first
    processing = m.Processing(matching=m.Matching(max_features=2048, sift_scale="original"))
    original = reconstruct(survey, tmp_path / "o", mode="known-poses", processing=processing,
                           feature_cache=folder / "cache")
    assert original.summary["reused_from_cache"]["features"] is False
    s_doubled = _keypoint_scales_px(folder / "a" / "database.db")
    s_original = _keypoint_scales_px(tmp_path / "o" / "database.db")
    # SIFT's finest scale is 1.6 × 2^(first octave) px: about 0.8 px on the doubled image
    assert s_doubled.min() < 1.2 < 1.5 < s_original.min()
    assert original.n_registered == doubled.n_registered == original.n_images
