"""Load a project file with both validation stages: XSD, then semantic checks.

``load_project`` is what every command uses: it returns a model that is safe to
render, or raises :class:`ProjectError` listing every problem as
``FILE:LINE:COLUMN: <element>: message`` (exit code 2). Nothing is written.
"""

from __future__ import annotations

import os
from pathlib import Path

from designer.project import model as m
from designer.project.problems import ProjectError, SourceMap
from designer.project.validate import semantic_problems
from designer.project.xml_read import read_project_file


def load_project(path: str | os.PathLike, check_files: bool = True) -> m.Project:
    """Read, schema-validate and semantically check ``path``; the valid project.

    Referenced files (texture, DEM, meshes) are resolved relative to the folder of
    ``path`` and checked when ``check_files`` is true.
    """
    return load_project_located(path, check_files)[0]


def load_project_located(path: str | os.PathLike, check_files: bool = True
                         ) -> tuple[m.Project, SourceMap]:
    """:func:`load_project` and where in the file each of its objects was read (to
    locate problems found later, e.g. over the built terrain)."""
    path = Path(path)
    project, smap = read_project_file(path)
    base = path.parent if check_files else None
    problems = semantic_problems(project, base, smap)
    if problems:
        raise ProjectError(str(path), problems)
    return project, smap


def validate_project(project: m.Project, base_dir: str | os.PathLike | None = None,
                     source: str = "<project>") -> None:
    """Raise ProjectError if an in-memory ``project`` has semantic problems.

    For models built in code (GUI, scripts, templates): problems name the element but
    carry no file position (line and column 0).
    """
    problems = semantic_problems(project, base_dir)
    if problems:
        raise ProjectError(source, problems)
