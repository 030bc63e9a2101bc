"""A real Cycles render through a 148° equidistant fisheye: detected GCP target centres
against the exported pixel coordinates (cases and checks: tests/render/accuracy.py)."""

from __future__ import annotations

import pytest

from tests.render.accuracy import (
    check_manifest_and_images,
    check_pycolmap_projects_like_the_odm_gcp_list,
    check_target_centres,
    render_case,
)

pytestmark = [pytest.mark.blender, pytest.mark.slow]


@pytest.fixture(scope="module", params=["fisheye 148 deg"])
def rendered(request, tmp_path_factory):
    return render_case(request.param, tmp_path_factory)


def test_target_centres_match_the_exported_pixel_coordinates(rendered):
    check_target_centres(rendered)


def test_pycolmap_projects_gcps_like_the_odm_gcp_list(rendered):
    check_pycolmap_projects_like_the_odm_gcp_list(rendered)


def test_manifest_and_images_are_complete(rendered):
    check_manifest_and_images(rendered)
