"""``designer check PROJECT.xml``: validate project files (XSD, then semantic checks).

The checks themselves, and their order: :mod:`designer.checks.project_checks`.

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
    from designer.checks.project_checks import load_checked, warning_lines
    from designer.project.problems import ProjectError
    from designer.project.summary import summary_line

    status = 0
    for path in args.projects:
        try:
            project, _ = load_checked(path, check_files=not args.no_files)
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
        for line in warning_lines(project, path, check_files=not args.no_files):
            print(line, file=sys.stderr)
    return status
