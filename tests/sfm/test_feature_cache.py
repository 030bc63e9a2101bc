"""Reconstructions of the same images share features and matches through the cache."""

from __future__ import annotations

import shutil

import pytest

from designer.sfm.feature_cache import FeatureCache
from designer.sfm.reconstruct import check_survey_folder, reconstruct

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def _database_rows(db_path, table: str) -> int:
    import sqlite3

    with sqlite3.connect(db_path) as db:
        return db.execute(f"SELECT COUNT(*) FROM {table}").fetchone()[0]


def test_a_second_reconstruction_of_the_same_images_reuses_features_and_matches(
        survey, tmp_path):
    cache = tmp_path / "cache"
    first = reconstruct(survey, tmp_path / "a", mode="known-poses", feature_cache=cache)
    second = reconstruct(survey, tmp_path / "b", mode="known-poses", feature_cache=cache)
    assert first.summary["reused_from_cache"] == {"features": False, "matches": False}
    assert second.summary["reused_from_cache"] == {"features": True, "matches": True}
    # the same database: the same keypoints and verified matches, the same points
    for table in ("keypoints", "two_view_geometries"):
        assert _database_rows(tmp_path / "a" / "database.db", table) == \
            _database_rows(tmp_path / "b" / "database.db", table) > 0
    assert second.n_points == first.n_points
    assert len(list(cache.glob("features-*/database.db"))) == 1
    assert len(list(cache.glob("matches-*/database.db"))) == 1


def test_a_changed_image_misses_the_cache(survey, tmp_path):
    import cv2

    cache = tmp_path / "cache"
    reconstruct(survey, tmp_path / "a", mode="known-poses", feature_cache=cache)
    changed = tmp_path / "survey"
    shutil.copytree(survey, changed)
    _, names = check_survey_folder(changed)
    image = next(changed.rglob(names[0]))
    pixels = cv2.imread(str(image), cv2.IMREAD_UNCHANGED)
    pixels[:8, :8] = 255 - pixels[:8, :8]  # another image: other features
    assert cv2.imwrite(str(image), pixels)
    result = reconstruct(changed, tmp_path / "b", mode="known-poses", feature_cache=cache)
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
