"""The texture variation on real Cycles renders: the tiled ground stops repeating with the
tile, the variation's files are part of the image's provenance, and a project without a
variation prepares exactly the job it prepared before the variation existed."""

from __future__ import annotations

import dataclasses
import json

import cv2
import numpy as np
import pytest

from designer.project import model as m
from designer.render.job import JOB_DIR, prepare_job
from designer.render.job_spec import MaterialSpec, RenderJob
from designer.render.job_terrain import BAKED_LIT_TEXTURE, BAKED_TEXTURE
from designer.render.pipeline import render_project
from designer.render.provenance import job_provenance
from tests.synthetic import small_survey, write_project_file

TILE_M = 10.0
GSD_M = 0.01 * 30.0 / 5.0  # pixel pitch × height / focal length


def nadir_project(variation: m.TextureVariation | None) -> m.Project:
    """Flat ground, 10 m grass tiles, one nadir photo from 30 m (19.2 × 14.4 m)."""
    p = small_survey(n_photos=1, samples=4, size_px=(320, 240))
    tex = dataclasses.replace(p.scene.texture, variation=variation)
    terrain = m.Terrain(p.scene.terrain.extent, m.FlatTerrain(0.0))
    scene = dataclasses.replace(p.scene, terrain=terrain, texture=tex, targets=None)
    photo = m.ExteriorOrientation("IMG_000.png", "cam", 3.0, 2.0, 30.0, 0.0, 0.0, 0.0)
    return dataclasses.replace(p, scene=scene, effects=None,
                               trajectory=m.Trajectory(exterior_orientations=(photo,)))


def tile_correlation(grey: np.ndarray) -> float:
    """Correlation of the image with itself one tile further east."""
    shift = round(TILE_M / GSD_M)
    a, b = grey[:, :-shift].ravel(), grey[:, shift:].ravel()
    return float(np.corrcoef(a, b)[0, 1])


def large_scale_change(grey: np.ndarray) -> float:
    """RMS change of the brightness smoothed over ~1 m between a point and the point one
    tile further east, relative to the mean brightness."""
    smooth = cv2.GaussianBlur(grey, (0, 0), sigmaX=1.0 / GSD_M)
    shift = round(TILE_M / GSD_M)
    diff = smooth[:, shift:] - smooth[:, :-shift]
    return float(np.sqrt(np.mean(diff**2)) / smooth.mean())


#: the variation of the rendered tests
VARIATION = m.TextureVariation(seed=5, scale_m=20.0, strength=0.5)


def _render_grey(project: m.Project, folder):
    """(summary, its IMG_000.png in grey levels) of ``project`` rendered in ``folder``."""
    path = write_project_file(project, folder)
    summary = render_project(path, folder / "out", workers=1)
    img = cv2.imread(str(summary.images_dir / "IMG_000.png"), cv2.IMREAD_GRAYSCALE)
    return summary, img.astype(np.float64)


@pytest.fixture(scope="module")
def varied(tmp_path_factory):
    """The nadir photo over the ground with VARIATION, baked as the renderer chooses (one
    render for the two tests that need it)."""
    return _render_grey(nadir_project(VARIATION), tmp_path_factory.mktemp("varied"))


@pytest.mark.blender
@pytest.mark.slow
def test_variation_breaks_the_tile_repeat_on_a_render(tmp_path, varied):
    grey = {"plain": _render_grey(nadir_project(None), tmp_path / "plain")[1],
            "varied": varied[1]}
    plain, varied = tile_correlation(grey["plain"]), tile_correlation(grey["varied"])
    # the plain tiled ground is the same one tile on; the varied one is not
    assert plain > 0.8
    assert varied < 0.5 and varied < plain - 0.4
    # the brightness varies at scales larger than the tile: smoothed over a metre, the
    # plain ground is the same one tile on, the varied ground is not
    change_plain, change_varied = large_scale_change(grey["plain"]), large_scale_change(
        grey["varied"])
    assert change_varied > 0.1 and change_varied > 3 * change_plain, (change_plain,
                                                                       change_varied)


def _job(tmp_path, variation, name):
    project = nadir_project(variation)
    path = write_project_file(project, tmp_path / name)
    prepared = prepare_job(project, path.parent, tmp_path / name / "out")
    return prepared, tmp_path / name / "out" / JOB_DIR


def test_absent_variation_prepares_the_job_of_before(tmp_path):
    prepared, job_dir = _job(tmp_path, None, "plain")
    terrain = next(o for o in prepared.job.objects if o.name == "terrain").materials[0]
    # the material the job held before the variation existed: same texture, tiles, light map
    # and strength (the light map's scale, nothing more)
    before = MaterialSpec(texture="texture.png", uv_tiles=(4.0, 4.0), interpolation="Linear",
                          lightmap="lightmap.png", strength=terrain.strength)
    assert terrain == before
    assert not list(job_dir.glob("variation*"))
    saved = json.loads((job_dir / "job.json").read_text())
    assert RenderJob.from_json(json.dumps(saved)) == prepared.job
    varied, varied_dir = _job(tmp_path, m.TextureVariation(1, 20.0, 0.3), "varied")
    v_terrain = next(o for o in varied.job.objects if o.name == "terrain").materials[0]
    # the blend baked into one linear image over the terrain (designer.render.texture_bake),
    # the static sun's light map multiplied in
    assert v_terrain.texture == BAKED_LIT_TEXTURE and (varied_dir / BAKED_LIT_TEXTURE).is_file()
    assert v_terrain.lightmap is None
    assert v_terrain.texture_colorspace == "Non-Color" and v_terrain.variation is None
    assert v_terrain.strength == pytest.approx(2 * terrain.strength)  # gain / 2 stored


def test_variation_is_part_of_the_scene_hash(tmp_path):
    parts = {}
    for name, variation in (("plain", None), ("a", m.TextureVariation(1, 20.0, 0.3)),
                            ("b", m.TextureVariation(1, 20.0, 0.4)),
                            ("c", m.TextureVariation(2, 20.0, 0.3))):
        prepared, job_dir = _job(tmp_path, variation, name)
        parts[name] = job_provenance(prepared.job, job_dir)[0].parts
    scenes = {k: v["scene"] for k, v in parts.items()}
    assert len(set(scenes.values())) == 4, scenes  # each change re-renders
    assert {v["pose"] for v in parts.values()} == {parts["plain"]["pose"]}


@pytest.mark.blender
@pytest.mark.slow
def test_the_baked_texture_renders_what_the_node_graph_renders(tmp_path, monkeypatch,
                                                                varied):
    """The bake (one lookup per sample) against the blend evaluated by Cycles' nodes
    (five lookups per sample, what the renderer does where a bake is too large)."""
    import designer.render.texture_bake as texture_bake

    # the bake: the module's render (MAX_BAKE_PX as it is); the nodes: no bake allowed
    monkeypatch.setattr(texture_bake, "MAX_BAKE_PX", 0)
    renders = {"baked": varied, "nodes": _render_grey(nadir_project(VARIATION),
                                                       tmp_path / "nodes")}
    for name, (summary, _) in renders.items():
        material = next(o for o in summary.prepared.job.objects
                        if o.name == "terrain").materials[0]
        assert (material.texture in (BAKED_TEXTURE, BAKED_LIT_TEXTURE)) == (name == "baked")
    baked, nodes = renders["baked"][1], renders["nodes"][1]
    assert np.corrcoef(baked.ravel(), nodes.ravel())[0, 1] > 0.99
    assert abs(baked.mean() - nodes.mean()) < 0.01 * nodes.mean()
    # codes of 255: the bake's interpolation of the warped lookup softens single texels
    # (2.3 on this ground, the variation fixed to the world at X −20..20 m)
    assert np.mean(np.abs(baked - nodes)) < 2.5
    # the same detail contrast (the bake softens only the finest texel detail)
    assert baked.std() == pytest.approx(nodes.std(), rel=0.03)


@pytest.mark.blender
@pytest.mark.slow
def test_tiles_render_what_one_bake_renders_across_their_seams(tmp_path, monkeypatch):
    """A bake too wide for one image, cut into tiles of 5.12 m (the photo sees a dozen
    and their seams), each frame loading its own: the same picture as the one bake, so
    no seam in colour or place. (Gentle relief on a 1 m grid: a tile holds its faces'
    texels, so the faces must be small beside it.)"""
    import designer.render.texture_bake as texture_bake
    import designer.render.tiled_bake as tiled_bake

    p = nadir_project(VARIATION)
    relief = m.ProceduralTerrain(seed=3, grid_spacing_m=1.0, roughness=0.3,
                                 min_height_m=-0.5, max_height_m=0.5, hill_size_m=20.0)
    p = dataclasses.replace(p, scene=dataclasses.replace(
        p.scene, terrain=m.Terrain(p.scene.terrain.extent, relief)))
    grey = {}
    for name, limit in (("one", texture_bake.MAX_BAKE_PX), ("tiled", 0)):
        monkeypatch.setattr(texture_bake, "MAX_BAKE_PX", limit)
        monkeypatch.setattr(tiled_bake, "TILE_CORE_PX", 256)
        summary, grey[name] = _render_grey(p, tmp_path / name)
    job = summary.prepared.job
    assert job.tiled_texture is not None
    (frame,) = job.frames
    assert len(frame.texture_tiles) >= 9
    seen = sorted((summary.prepared.job_path.parent).glob("texture_tile_*.tif"))
    assert len(seen) == len(frame.texture_tiles)  # only the tiles it sees are baked
    one, tiled = grey["one"], grey["tiled"]
    # the light map folded in per tile rounds a 16-bit code apart from the one bake's
    # at most: an 8-bit code here and there
    assert np.abs(tiled - one).max() <= 1
    assert np.mean(tiled != one) < 0.01


def _edge_project(variation: m.TextureVariation) -> m.Project:
    """Flat ground 40 m wide, one photo from 30 m near its east edge, tilted east: it
    sees about 20 m past the terrain, where the surroundings continue it."""
    p = nadir_project(variation)
    photo = m.ExteriorOrientation("IMG_000.png", "cam", 14.0, 0.0, 30.0, 0.0, -20.0, 0.0)
    return dataclasses.replace(p, trajectory=m.Trajectory(exterior_orientations=(photo,)))


@pytest.mark.blender
@pytest.mark.slow
def test_a_detail_and_a_coarse_bake_render_what_one_bake_renders(tmp_path, monkeypatch):
    """Surroundings too wide for one bake: a detail bake near, a coarse one far (one
    lookup per sample each) against the single bake of the whole terrain."""
    import designer.render.texture_bake as texture_bake

    variation = m.TextureVariation(seed=5, scale_m=20.0, strength=0.5)
    grey, jobs = {}, {}
    # 10 m tiles of 500 texels; the declared 40 m take 2000 px: a 2600 px limit lets
    # the detail bake reach one tile into the surroundings
    for name, limit in (("one", texture_bake.MAX_BAKE_PX), ("two", 2600)):
        monkeypatch.setattr(texture_bake, "MAX_BAKE_PX", limit)
        path = write_project_file(_edge_project(variation), tmp_path / name)
        summary = render_project(path, tmp_path / name / "out", workers=1)
        jobs[name] = summary.prepared
        img = cv2.imread(str(summary.images_dir / "IMG_000.png"), cv2.IMREAD_GRAYSCALE)
        grey[name] = img.astype(np.float64)
    terrain = {k: next(o for o in j.job.objects if o.name == "terrain")
               for k, j in jobs.items()}
    assert len(terrain["one"].materials) == 1 and len(terrain["two"].materials) == 2
    index = np.load(jobs["two"].job_path.parent / "terrain.npz")["material_index"]
    assert set(np.unique(index)) == {0, 1}
    one, two = grey["one"], grey["two"]
    assert (one < 3).mean() == 0 and (two < 3).mean() == 0  # ground in every pixel
    assert np.corrcoef(one.ravel(), two.ravel())[0, 1] > 0.9
    assert abs(one.mean() - two.mean()) < 0.02 * one.mean()
    # the western half of the picture sees the declared terrain: the same detail bake
    west = slice(None), slice(0, one.shape[1] // 2)
    assert np.mean(np.abs(one[west] - two[west])) < 1.0


def test_a_second_preparation_keeps_the_bake_of_the_same_inputs(tmp_path, monkeypatch):
    """A resumed render prepares its job again: the bake the job folder holds from the
    same inputs (texture, variation, light map) is kept, not baked again; a changed
    variation is baked anew."""
    from designer.render import job_terrain
    from designer.render.job import prepare_job

    calls = []
    real = job_terrain.bake_varied_texture
    monkeypatch.setattr(job_terrain, "bake_varied_texture",
                        lambda *a: calls.append(1) or real(*a))
    variation = m.TextureVariation(1, 20.0, 0.3)
    project = nadir_project(variation)
    out = tmp_path / "out"
    prepare_job(project, tmp_path, out)
    lit = out / ".designer-job" / BAKED_LIT_TEXTURE
    first = lit.read_bytes()
    assert calls == [1]
    lit.touch()
    stamp = lit.stat().st_mtime_ns
    prepare_job(project, tmp_path, out)
    assert calls == [1] and lit.stat().st_mtime_ns == stamp  # kept as it was
    other = nadir_project(dataclasses.replace(variation, strength=0.4))
    prepare_job(other, tmp_path, out)
    assert calls == [1, 1] and lit.read_bytes() != first
    # a bake whose key file went missing (a run stopped between the two) is made again
    (out / ".designer-job" / (BAKED_LIT_TEXTURE + ".key")).unlink()
    prepare_job(other, tmp_path, out)
    assert calls == [1, 1, 1]
