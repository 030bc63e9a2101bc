"""``designer new PROJECT.xml --template NAME``: write an example project to start from.

Companion files the template references (a mesh, a texture image) are written next to
the project file. Nothing is overwritten without ``--force``; every file is written
atomically, the project file last.
"""

from __future__ import annotations

from pathlib import Path

TEMPLATES = ("survey", "survey-ideal", "validation-cube", "psf", "texture")


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "new", help="write an example project from a template",
        description="Write a schema-valid example project. Templates: survey (the example "
                    "survey: 100 m hills, 10 GCPs, grid flight), validation-cube (a cube and "
                    "24 orbit photos), psf (slanted edges for the point spread function), "
                    "texture (an image texture tiled over a plane).",
    )
    parser.add_argument("project", type=Path, metavar="PROJECT.xml", help="file to write")
    parser.add_argument("--template", choices=TEMPLATES, default="survey",
                        help="which example (default: survey)")
    parser.add_argument("--force", action="store_true", help="overwrite existing files")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.project.new import write_template

    written = write_template(args.project, args.template, force=args.force)
    print(f"wrote {args.project} (template {args.template})"
          + "".join(f", {p}" for p in written[:-1]))
    print(f"next: designer check {args.project}")
    return 0
