"""Every check ``designer check`` runs on a project file, in the order it reports them.

First the project's own validation (:func:`designer.project.load.load_project_located`:
the schema, then the semantic checks of ``designer.project.validate*`` and the referenced
files), then the camera stations against the ground (:mod:`.station_clearance`), which
refuse the project like a validation problem. A valid project is then weighed for what
degrades results, as warnings that leave it valid: images seeing past the terrain
(:func:`designer.survey.surroundings.surroundings_warning`), the hard cases
(:mod:`.hard_cases`) and places beyond the ground a terrain file holds
(:mod:`.terrain_reach`). Without the files (``check_files`` False) only what needs no
file is weighed: the lenses and optics.
"""

from __future__ import annotations

from pathlib import Path

from designer.errors import DesignerError
from designer.project import model as m
from designer.project.problems import ProjectError, SourceMap


def load_checked(path: Path, check_files: bool = True) -> tuple[m.Project, SourceMap]:
    """The project at ``path`` and where its elements stand in the file, once it has
    passed every check that refuses a project (ProjectError, every problem listed):
    validation and, with ``check_files``, the camera stations' clearance."""
    from designer.project.load import load_project_located

    path = Path(path)
    project, smap = load_project_located(path, check_files=check_files)
    if check_files:  # the terrain may be a file
        refuse_low_stations(project, smap, path)
    return project, smap


def refuse_low_stations(project: m.Project, smap: SourceMap, path: Path) -> None:
    """Raise a ProjectError when camera stations lie under the terrain, a building or a
    plant (:mod:`.station_clearance`): their images and figures are meaningless."""
    from designer.checks.station_clearance import clearance_issues

    issues = clearance_issues(project, Path(path).parent)
    if issues:
        raise ProjectError(str(path), [smap.locate(i) for i in issues])


def warning_lines(project: m.Project, path: Path, check_files: bool = True) -> list[str]:
    """The warnings of a valid ``project`` read from ``path``, one line each
    (``warning: PATH: <element>: message; fix``): images seeing past the terrain, the
    hard cases, places beyond a terrain file's ground."""
    path = Path(path)
    lines = []
    if check_files:
        surroundings = _surroundings_warning(project, path)
        if surroundings:
            lines.append(f"warning: {path}: <terrain>: {surroundings}")
    lines += [w.line(path) for w in _hard_case_warnings(project, path, check_files)]
    if check_files:
        from designer.checks.terrain_reach import terrain_reach_warnings

        lines += [w.line(path) for w in terrain_reach_warnings(project, path.parent)]
    return lines


def _surroundings_warning(project: m.Project, path: Path) -> str | None:
    from designer.survey.surroundings import surroundings_warning

    try:
        return surroundings_warning(project, path.parent)
    except DesignerError:  # the flight cannot be planned: check says why elsewhere
        return None


def _hard_case_warnings(project: m.Project, path: Path, check_files: bool) -> list:
    """Nearly collinear control, GSD against texel, a lens close to its fold, a thin
    network, optics beyond a survey's (:mod:`.hard_cases`, docs/hard-cases.md); without
    the files only the lenses and optics."""
    from designer.checks.hard_cases import (
        distortion_warning,
        hard_case_warnings,
        optics_warnings,
    )

    if check_files:
        return hard_case_warnings(project, path.parent)
    warnings = [w for cam in project.cameras
                if (w := distortion_warning(cam, project.render.resolution_scale))]
    return warnings + optics_warnings(project)
