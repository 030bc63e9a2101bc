"""One-line description of a valid project (``designer check``)."""

from __future__ import annotations

import os

from designer.project import model as m


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def summary_line(path: str | os.PathLike, project: m.Project) -> str:
    """e.g. ``x.xml: valid designer project 1.0 — terrain procedural 100 x 100 m, 1 camera,
    flight plan, 10 GCPs (7 control, 3 check)``."""
    terrain = project.scene.terrain
    e = terrain.extent
    parts = [f"terrain {terrain.kind} {e.width_m:g} x {e.length_m:g} m",
             _plural(len(project.cameras), "camera")]
    readouts = sorted({c.readout_s for c in project.cameras if c.readout_s > 0})
    if readouts:
        parts.append("rolling shutter (" + ", ".join(f"{1000 * r:g}" for r in readouts)
                     + " ms readout)")
    photos = len(project.trajectory.exterior_orientations)
    if photos:
        parts.append(_plural(photos, "photo"))
    if project.trajectory.flight_plan is not None:
        parts.append("flight plan")
    targets = project.targets
    control = sum(t.role == "control" for t in targets)
    check = len(targets) - control
    parts.append(f"{_plural(len(targets), 'GCP')} ({control} control, {check} check)"
                 if targets else "no GCPs")
    if project.scene.objects:
        parts.append(_plural(len(project.scene.objects), "object"))
    if project.scene.buildings:
        parts.append(_plural(len(project.scene.buildings), "building"))
    veg = project.scene.vegetation
    if veg is not None:
        e = project.scene.terrain.extent
        n = sum(g.density_per_m2 for g in veg.plants) * e.width_m * e.length_m
        parts.append(f"{_plural(len(veg.plants), 'plant group')} (about {n:,.0f} plants"
                     + (", wind" if veg.wind is not None else "") + ")")
    return (f"{path}: valid designer project {project.schema_version} — " + ", ".join(parts))
