"""The Flight panel's figures past the terrain's edge (Qt-free state): its images see the
surroundings' ground there, as ``designer plan`` analyses them, or void without
surroundings; never the side of the solid ground below the surface."""

from __future__ import annotations

import pytest

from designer.checks.plan_report import plan_project, plan_summary
from designer.gui.state import derived, edits, files
from designer.gui.state.plan_figures import compute_plan_figures
from designer.project import model as m

LOW_M, HIGH_M = -15.0, 15.0


def hilly_flight_past_the_edge() -> m.Project:
    """The blank project on procedural hills, its whole terrain flown at 80 m: the edge
    lines' images look far past the terrain."""
    p = files.blank_project()
    p = edits.replace_path(p, "scene.terrain.source",
                           m.ProceduralTerrain(7, 1.0, 0.3, LOW_M, HIGH_M, 60.0))
    return edits.set_flight(edits.ensure_flight_plan(p), area=edits.terrain_rectangle(p),
                            altitude_agl_m=80.0)


@pytest.mark.parametrize("surroundings", ["auto", "none"])
def test_figures_past_the_edge_are_designer_plans(surroundings, tmp_path):
    project = edits.replace_path(hilly_flight_past_the_edge(), "scene.terrain.surroundings",
                                 surroundings)
    terrain = derived.compute_terrain(project, tmp_path)
    stations = derived.compute_stations(project, terrain)
    figures = compute_plan_figures(project, terrain, stations, None)
    s = plan_summary(plan_project(project, tmp_path))
    assert figures.n_images == s["n_images"]
    for name in ("front_overlap_median", "front_overlap_p05", "side_overlap_median",
                 "side_overlap_p05"):
        assert getattr(figures, name) == pytest.approx(s[name], abs=1e-9), name
    assert figures.gsd_median_m == pytest.approx(s["gsd_centre_m_median"])
    assert figures.images_over_area == s["stations_over_area"]
    # the count of images looking at the terrain is the declared terrain's
    assert figures.images_over_terrain == figures.images_over_area < figures.n_images
    # footprints lie on the ground (the surface, or the plane past its edge), not on
    # the side of the solid ground below it
    z = stations.geometry.footprint_points[:, 2]
    assert len(z) and z.min() >= LOW_M - 0.5 and z.max() <= HIGH_M + 0.5, (z.min(), z.max())
