"""``designer export-flight PROJECT.xml --format qgc|kml|wpml -o FILE``: the planned flight
for QGroundControl, Google Earth / GIS or DJI Pilot 2."""

from __future__ import annotations

from pathlib import Path

from designer.cli.flight_heights import add_height_arguments


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "export-flight", help="write the project's flight plan for a drone or a map",
        description=(
            "Write the project's planned exposures (explicit photos, then the flight plan's "
            "stations without pose noise) as a QGroundControl .plan (waypoint mission with "
            "a camera-trigger distance), a KML/KMZ of flight lines and photo points, or a "
            "DJI WPML .kmz (template.kml + waylines.wpml) for DJI Pilot 2. Terrain-following "
            "plans fly each waypoint at its height above the terrain. See docs/real-data.md."),
    )
    parser.add_argument("project", type=Path, help="project XML file")
    parser.add_argument("--format", required=True, choices=("qgc", "kml", "wpml"),
                        help="qgc: .plan; kml: .kml or .kmz; wpml: DJI .kmz")
    parser.add_argument("-o", "--output", required=True, type=Path, metavar="FILE",
                        help="file to write (.plan, .kml/.kmz, .kmz)")
    add_height_arguments(parser, default="relative",
                         offset_example="the geoid undulation for WPML's ellipsoidal heights")
    parser.add_argument("--speed-m-s", type=float, default=5.0,
                        help="flight speed (m/s, default 5)")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.flight.export import export_flight
    from designer.project import load_project

    project = load_project(args.project)
    # designer.flight names absolute heights "amsl"
    altitude = "amsl" if args.altitude == "absolute" else args.altitude
    spec = export_flight(
        project, args.project.parent, args.format, args.output, altitude=altitude,
        takeoff_height_m=args.takeoff_height_m, height_offset_m=args.height_offset_m,
        speed_m_s=args.speed_m_s)
    lines = len(spec.lines)
    # KML has no heights relative to the take-off point: it always gets AMSL heights
    # (altitudeMode absolute, designer.flight.kml)
    heights = ("AMSL (KML altitudeMode absolute; --altitude applies to qgc and wpml)"
               if args.format == "kml" else args.altitude)
    print(f"wrote {args.output}: {len(spec.exposures)} photos on {lines} line"
          f"{'s' if lines != 1 else ''} ({args.format}, heights {heights}"
          f"{', terrain following' if spec.terrain_following else ''})")
    return 0
