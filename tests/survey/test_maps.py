import numpy as np
import pytest

from designer.core.raycast import TerrainRaycaster
from designer.survey import area, coverage
from designer.survey.flight import plan_flight
from tests.synthetic import ORIGIN_WORLD, hilly_terrain, phantom4

pytest.importorskip("matplotlib")

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_maps_are_written_atomically_as_png(tmp_path):
    from designer.survey.maps import write_coverage_map, write_gsd_map

    hf = hilly_terrain(x0=ORIGIN_WORLD[:2][0], y0=ORIGIN_WORLD[:2][1])
    poly = area.rectangle(50, 50, 350, 350) + ORIGIN_WORLD[:2]
    plan = plan_flight(poly, phantom4(), altitude_agl_m=80.0, heightfield=hf,
                       altitude_mode="terrain_following")
    grid = coverage.ground_grid(hf, poly, cell_m=10.0)
    cover = coverage.coverage_map(grid, plan.C_world, plan.R_cam_to_world, phantom4(),
                                  TerrainRaycaster(hf))
    count_png = write_coverage_map(tmp_path / "coverage.png", cover, area=poly,
                                   stations_xy=plan.C_world[:, :2])
    gsd_png = write_gsd_map(tmp_path / "gsd.png", cover, area=poly, statistic="min")
    for path in (count_png, gsd_png):
        data = path.read_bytes()
        assert data.startswith(PNG_SIGNATURE) and len(data) > 10_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["coverage.png", "gsd.png"]
    with pytest.raises(ValueError, match="statistic"):
        write_gsd_map(tmp_path / "x.png", cover, statistic="max")
    assert not (tmp_path / "x.png").exists()
    # an unwritable target leaves nothing behind
    with pytest.raises(OSError):
        write_coverage_map(tmp_path / "missing" / "c.png", cover)
    assert np.isfinite(cover.gsd_mean_m[grid.inside_area]).all()
