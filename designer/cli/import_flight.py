"""``designer import-flight SOURCE --base PROJECT.xml -o NEW.xml``: a flown survey (images,
geo.txt or reference CSV) as a project that replays it over the base project's scene."""

from __future__ import annotations

from pathlib import Path

from designer.cli.flight_heights import add_height_arguments


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "import-flight", help="turn a flown survey into a project that replays it",
        description=(
            "Read the photo positions and attitudes of a flown survey — a folder of images "
            "(EXIF GPS + DJI XMP gimbal angles), an OpenDroneMap geo.txt or a Metashape/"
            "Pix4D-style reference CSV — convert them to the base project's CRS as explicit "
            "exterior orientations, pick the camera from the metadata, and write a project "
            "with the base project's scene. See docs/real-data.md."),
    )
    parser.add_argument("source", type=Path,
                        help="folder of images, geo.txt (.txt) or reference CSV (.csv)")
    parser.add_argument("--base", required=True, type=Path, metavar="PROJECT.xml",
                        help="project giving the scene, CRS and camera")
    parser.add_argument("-o", "--output", required=True, type=Path, metavar="NEW.xml",
                        help="project file to write")
    add_height_arguments(parser, default="absolute",
                         offset_example="minus the geoid undulation to turn ellipsoidal "
                                        "into orthometric heights")
    parser.add_argument("--csv-crs", default=None, metavar="EPSG:CODE",
                        help="CRS of a CSV's X/Y columns (default: the base project's)")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.flight.importer import import_flight

    project = import_flight(
        args.source, args.base, args.output, height=args.altitude,
        takeoff_height_m=args.takeoff_height_m, height_offset_m=args.height_offset_m,
        csv_crs=args.csv_crs)
    eos = project.trajectory.exterior_orientations
    print(f"wrote {args.output}: {len(eos)} photos with camera '{eos[0].camera}'")
    return 0
