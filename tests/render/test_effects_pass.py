"""Camera effects from kept raw renders: a project that differs from a rendered one only
in its camera effects is finished without Cycles, byte for byte as a full render."""

from __future__ import annotations

from pathlib import Path

import pytest

from designer.errors import DesignerError
from designer.project import model as m
from designer.render.manifest import read_manifest
from designer.render.pipeline import render_project
from designer.render.void_share import VOID_MAP_SUFFIX
from tests.synthetic import small_survey, write_project_file


def _project(noise_seed: int) -> m.Project:
    effects = m.Effects(
        vignetting=m.Vignetting(0.2),
        sensor=m.Sensor(full_well_e=20000.0, read_noise_e=3.0, dark_current_e_per_s=0.5,
                        exposure_time_s=0.001, adc_bits=12, exposure_scale=0.8,
                        seed=noise_seed))
    return small_survey(n_photos=3, samples=4, size_px=(240, 180), effects=effects,
                        distortion=m.BrownConradyDistortion(k1=-0.05))


@pytest.mark.blender
@pytest.mark.slow
def test_an_effects_pass_equals_a_full_render(tmp_path):
    a = write_project_file(_project(1), tmp_path / "a")
    raw = tmp_path / "raw"
    first = render_project(a, tmp_path / "a" / "out", workers=1, keep_raw=raw)
    stems = sorted(Path(n).stem for n in first.prepared.job.image_names.values())
    # each raw render, and its void map for the pass to record
    assert sorted(p.name for p in raw.iterdir()) == sorted(
        [*first.prepared.job.image_names.values(), *(s + VOID_MAP_SUFFIX for s in stems)])
    b = write_project_file(_project(2), tmp_path / "b")
    passed = render_project(b, tmp_path / "b" / "pass", raw_from=raw)
    full = render_project(b, tmp_path / "b" / "full", workers=1)
    names = sorted(full.prepared.job.image_names.values())
    for name in names:
        assert (passed.images_dir / name).read_bytes() == (full.images_dir / name).read_bytes()
        # and differ from the first project's (another noise draw)
        assert (passed.images_dir / name).read_bytes() != (first.images_dir / name).read_bytes()
    assert all("cycles_s" not in s for s in passed.report.stages.values())
    # the pass records the void its raw renders saw: the full render's
    assert passed.report.void_share == full.report.void_share
    assert sorted(full.report.void_share) == list(range(len(names)))
    assert read_manifest(passed.out_dir)["void"] == read_manifest(full.out_dir)["void"]
    assert (raw / names[0]).is_file()  # the cache is kept for the next pass
    # a raw folder that lacks a frame: one line, nothing rendered
    (raw / names[0]).unlink()
    with pytest.raises(DesignerError, match="no raw render of frames"):
        render_project(b, tmp_path / "b" / "again", raw_from=raw)
