"""Semantic checks of a project: what the XSD cannot say.

Cross references (camera ids), uniqueness (photo names, GCP ids), geometry (GCPs
inside the terrain, a simple flight polygon), physics (square pixels, an invertible
lens model), files (exist, are images/meshes/DEMs) and, again, every range the XSD
states, so that a model built in code (GUI, scripts) gets the same checks as a file.
"""

from __future__ import annotations

from pathlib import Path

from designer.project import model as m
from designer.project.problems import Issue, Problem, SourceMap, unlocated
from designer.project.validate_camera import camera_issues
from designer.project.validate_declared import declared_issues
from designer.project.validate_processing import processing_issues
from designer.project.validate_scene import scene_issues
from designer.project.validate_shared import finite_issues
from designer.project.validate_trajectory import (
    effects_issues,
    render_output_issues,
    trajectory_issues,
)
from designer.project.validate_world import world_issues

#: the project's text fields, as their problems name them
_WHAT = {"name": "project's name", "crs": "coordinate reference system (CRS)"}


def semantic_issues(project: m.Project, base_dir: str | Path | None = None) -> list[Issue]:
    """Every semantic problem of ``project``, in file order as far as possible.

    Referenced files are checked only when ``base_dir`` (the folder of the project
    file, to which their paths are relative) is given.
    """
    base = None if base_dir is None else Path(base_dir)
    out: list[Issue] = []
    for tag, text in (("name", project.name), ("crs", project.crs)):
        if not text.strip():
            out.append(Issue(project, tag, f"the {_WHAT[tag]} is empty; fill it in"))
    out += finite_issues(project.origin)
    out += scene_issues(project.scene, base)
    out += _cameras(project)
    out += trajectory_issues(project)
    out += world_issues(project)
    out += effects_issues(project.effects)
    out += render_output_issues(project)
    out += processing_issues(project)
    out += declared_issues(project)
    return out


def _cameras(project: m.Project) -> list[Issue]:
    out = []
    if not project.cameras:
        out.append(Issue(project, "cameras", "the project has no camera; add one"))
    seen: dict[str, int] = {}
    for cam in project.cameras:
        seen[cam.id] = seen.get(cam.id, 0) + 1
    for cam_id, count in seen.items():
        if count > 1:
            cam = next(c for c in project.cameras if c.id == cam_id)
            out.append(Issue(cam, "camera", f"camera id '{cam_id}' is used by {count} "
                                            "cameras; give each camera its own id", attr="id"))
    for cam in project.cameras:
        out += camera_issues(cam, project.render.resolution_scale)
    return out


def semantic_problems(
    project: m.Project, base_dir: str | Path | None = None, smap: SourceMap | None = None,
) -> list[Problem]:
    """:func:`semantic_issues` as :class:`Problem` lines, located when ``smap`` is given."""
    issues = semantic_issues(project, base_dir)
    problems = [smap.locate(i) if smap is not None else unlocated(i) for i in issues]
    return sorted(problems, key=lambda p: (p.line, p.column)) if smap is not None else problems
