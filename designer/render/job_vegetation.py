"""The vegetation of a render job: per plant group a template mesh and its plants'
placements (two .npz beside job.json), posed per frame by the worker at the frame's
time (docs/world.md, Vegetation and wind)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from designer.project import model as m
from designer.render.job_files import save_npz
from designer.render.job_spec import MaterialSpec, PlantSetSpec, WindSpec
from designer.scene.vegetation import WOOD_ALBEDO, PlantSet, place_vegetation

#: Blender object-name prefix of a plant group
PLANTS_PREFIX = "plants:"


def vegetation_job(project: m.Project, base_dir: Path, ground, job_dir: Path,
                   origin: np.ndarray) -> tuple[tuple[PlantSetSpec, ...], WindSpec | None,
                                                list[PlantSet]]:
    """(the job's plant-group specs, its wind, the placed plants). Bases are written
    local (world − origin); groups without a plant are left out."""
    veg = project.scene.vegetation
    if veg is None:
        return (), None, []
    sets = place_vegetation(project, base_dir, ground)
    specs = []
    for plants in sets:
        if not len(plants):
            continue
        t = plants.template
        template, instances = f"plants_{plants.group}.npz", f"plants_{plants.group}_at.npz"
        save_npz(Path(job_dir) / template, vertices_local=t.vertices, faces=t.faces,
                 material_index=t.material_index)
        save_npz(Path(job_dir) / instances, base_local=plants.base_world - origin,
                 scale=plants.scale, yaw_rad=plants.yaw_rad, phase_rad=plants.phase_rad)
        specs.append(PlantSetSpec(
            f"{PLANTS_PREFIX}{plants.group}", template, instances,
            (MaterialSpec(color=plants.albedo_rgb), MaterialSpec(color=WOOD_ALBEDO))))
    wind = veg.wind
    wind_spec = None if wind is None else WindSpec(float(wind.amplitude_deg),
                                                   float(wind.gust_period_s),
                                                   float(wind.direction_deg))
    return tuple(specs), wind_spec, sets
