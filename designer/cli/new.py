"""``designer new PROJECT.xml``: write a project to start from.

``--template NAME`` writes an example project; companion files it references (a mesh, a
texture image) are written next to the project file. ``--site DEM.tif [--orthophoto
ORTHO.tif]`` writes a project for a real site, its CRS, origin and extent taken from the
files (which stay where they are; the project refers to them by relative path). Nothing
is overwritten without ``--force``; every file is written atomically, the project file
last.
"""

from __future__ import annotations

from pathlib import Path

from designer.errors import DesignerError

TEMPLATES = ("survey", "survey-ideal", "survey-dynamic", "survey-structures", "survey-block",
             "validation-cube", "psf", "texture")


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "new", help="write an example project from a template, or a project for a real site",
        description="Write a schema-valid project. Templates: survey (the example "
                    "survey: 100 m hills, 10 GCPs, grid flight), survey-block (the example "
                    "at a real survey's size: 12 ha, about 720 images, 16 control and 9 "
                    "check GCPs), validation-cube (a cube and 24 orbit photos), psf "
                    "(slanted edges for the point spread function), "
                    "texture (an image texture tiled over a plane). With --site: a project "
                    "for a real site from a GeoTIFF DEM (any projected CRS in metres, or "
                    "geographic degrees, reprojected to its UTM zone) and a georeferenced "
                    "orthophoto GeoTIFF draped by its geotransform; CRS, origin and terrain "
                    "extent come from the files, a grid flight and six GCP targets are laid "
                    "out over them.",
    )
    parser.add_argument("project", type=Path, nargs="?", metavar="PROJECT.xml",
                        help="file to write (or give it with -o)")
    parser.add_argument("-o", "--output", type=Path, metavar="PROJECT.xml",
                        help="file to write (instead of the positional PROJECT.xml)")
    parser.add_argument("--template", choices=TEMPLATES, default=None,
                        help="which example (default: survey)")
    parser.add_argument("--site", type=Path, metavar="DEM.tif",
                        help="a real site: its DEM (GeoTIFF)")
    parser.add_argument("--orthophoto", type=Path, metavar="ORTHO.tif",
                        help="with --site: the site's orthophoto (GeoTIFF), draped exactly")
    parser.add_argument("--force", action="store_true", help="overwrite existing files")
    parser.set_defaults(func=run)


def run(args) -> int:
    if (args.project is None) == (args.output is None):
        raise DesignerError("designer new: give the project file once, as PROJECT.xml or "
                            "with -o PROJECT.xml")
    path = args.project or args.output
    if args.site is None:
        if args.orthophoto is not None:
            raise DesignerError("designer new: --orthophoto needs --site DEM.tif")
        from designer.project.new import write_template

        name = args.template or "survey"
        written = write_template(path, name, force=args.force)
        print(f"wrote {path} (template {name})" + "".join(f", {p}" for p in written[:-1]))
    else:
        if args.template is not None:
            raise DesignerError("designer new: give either --template or --site, not both")
        from designer.project.new import write_new_project
        from designer.survey.site_project import site_project

        project = site_project(args.site, args.orthophoto, path)
        write_new_project(path, project, {}, args.force, str(path), check_files=True)
        e = project.scene.terrain.extent
        print(f"wrote {path} (site {args.site}"
              + (f" + {args.orthophoto}" if args.orthophoto else "") + f"): {project.crs}, "
              f"extent X {e.min_X:.1f}..{e.max_X:.1f}, Y {e.min_Y:.1f}..{e.max_Y:.1f}, "
              f"origin ({project.origin.E0:.0f}, {project.origin.N0:.0f}, "
              f"{project.origin.H0:.2f})")
    print(f"next: designer check {path}")
    return 0
