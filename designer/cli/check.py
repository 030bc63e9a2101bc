"""``designer check PROJECT.xml``: validate project files (XSD, then semantic checks).

Prints one summary line per valid file and exits 0; otherwise prints every problem
as ``FILE:LINE:COLUMN: <element>: message`` on stderr and exits 2.
"""

from __future__ import annotations

import sys
from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "check", help="validate project files and print a summary",
        description="Validate project files: first against the XML schema, then the "
                    "semantic checks (cameras, GCPs, flight plan, referenced files). Every "
                    "problem is listed as FILE:LINE:COLUMN: message; exit code 2 if any.",
    )
    parser.add_argument("projects", nargs="+", type=Path, metavar="PROJECT.xml",
                        help="project file(s) to check")
    parser.add_argument("--no-files", action="store_true",
                        help="do not check that referenced files exist and are readable")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.project.load import load_project_located
    from designer.project.problems import ProjectError
    from designer.project.summary import summary_line

    status = 0
    for path in args.projects:
        try:
            project, smap = load_project_located(path, check_files=not args.no_files)
            _refuse_low_stations(path, project, smap, args)
        except ProjectError as error:
            for line in error.lines:
                print(line, file=sys.stderr)
            count = len(error.problems)
            print(f"{path}: {count} problem{'s' if count != 1 else ''}; not a valid designer "
                  "project", file=sys.stderr)
            status = 2
            continue
        except Exception as error:  # a bug, but bad input must never show a traceback
            print(f"{path}:1:1: <project>: internal error while checking this file "
                  f"({type(error).__name__}: {error}); please report it with the file",
                  file=sys.stderr)
            status = 2
            continue
        print(summary_line(path, project))
        _warn_surroundings(path, project, args)
        _warn_hard_cases(path, project, args)
        _warn_terrain_reach(path, project, args)
    return status


def _refuse_low_stations(path: Path, project, smap, args) -> None:
    """Raise a ProjectError when camera stations lie under the terrain, a building or a
    plant (designer.survey.station_clearance): their images and figures are meaningless.
    Not with --no-files (the terrain may be a file)."""
    if args.no_files:
        return
    from designer.project.problems import ProjectError
    from designer.survey.station_clearance import clearance_issues

    issues = clearance_issues(project, path.parent)
    if issues:
        raise ProjectError(str(path), [smap.locate(i) for i in issues])


def _warn_surroundings(path: Path, project, args) -> None:
    """A warning (stderr, exit status unchanged) when images would see past the terrain."""
    if args.no_files:
        return
    from designer.errors import DesignerError
    from designer.survey.surroundings import surroundings_warning

    try:
        warning = surroundings_warning(project, path.parent)
    except DesignerError:  # the flight cannot be planned: check says why elsewhere
        warning = None
    if warning:
        print(f"warning: {path}: <terrain>: {warning}", file=sys.stderr)


def _warn_hard_cases(path: Path, project, args) -> None:
    """Warnings (stderr, exit status unchanged) where the project walks into a case that
    degrades results: nearly collinear control, GSD against texel, a lens close to its
    fold (designer.survey.hard_cases, docs/hard-cases.md)."""
    from designer.survey.hard_cases import (
        distortion_warning,
        hard_case_warnings,
        optics_warnings,
    )

    if args.no_files:  # the terrain may be a file: only the lens and optics are checked
        warnings = [w for cam in project.cameras
                    if (w := distortion_warning(cam, project.render.resolution_scale))]
        warnings += optics_warnings(project)
    else:
        warnings = hard_case_warnings(project, path.parent)
    for warning in warnings:
        print(warning.line(path), file=sys.stderr)


def _warn_terrain_reach(path: Path, project, args) -> None:
    """Warnings (stderr, exit status unchanged) for GCPs, buildings and flight-area
    vertices outside the ground a DEM or terrain mesh holds
    (designer.survey.terrain_reach)."""
    if args.no_files:
        return
    from designer.survey.terrain_reach import terrain_reach_warnings

    for warning in terrain_reach_warnings(project, path.parent):
        print(warning.line(path), file=sys.stderr)
