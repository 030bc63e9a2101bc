"""``designer plan PROJECT.xml``: image count, GSD, overlaps, coverage and GCP visibility."""

from __future__ import annotations

import json
import sys
from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "plan", help="report what a project's flight will deliver, before rendering",
        description=(
            "Plan the project's flight over its real terrain and report the image count, GSD, "
            "footprint, achieved overlaps (measured by projecting real footprints), coverage, "
            "the images that see each GCP unoccluded, and the estimated render time, with "
            "warnings (nearly collinear control and a network too thin for SfM as "
            "'designer check' words them). A terrain mesh cannot be analysed: only those "
            "two warnings are printed before the refusal. Camera stations under the "
            "terrain, a building or a plant are refused as 'designer check' refuses them."),
    )
    parser.add_argument("project", type=Path, help="project XML file")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    parser.add_argument("--maps", type=Path, default=None, metavar="DIR",
                        help="write coverage and GSD maps (PNG) into DIR")
    parser.add_argument("--cell-m", type=float, default=None,
                        help="ground cell size of the coverage analysis (m)")
    parser.add_argument("--write-poses", type=Path, default=None, metavar="OUT.xml",
                        help="write the project with the sampled stations as explicit "
                             "exterior orientations (reproducible without the planner)")
    parser.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from designer.errors import DesignerError
    from designer.project import model as m
    from designer.project import write_project
    from designer.project.load import load_project_located
    from designer.survey.hard_cases import control_and_network_warnings
    from designer.survey.plan_report import (
        format_plan,
        plan_project,
        plan_summary,
        project_with_explicit_poses,
    )
    from designer.survey.station_clearance import refuse_low_stations

    if args.cell_m is not None and not args.cell_m > 0:
        raise DesignerError(f"--cell-m {args.cell_m}: give a cell size > 0 m")
    project, smap = load_project_located(args.project)
    refuse_low_stations(project, smap, args.project)
    if isinstance(project.scene.terrain.source, m.MeshTerrain):
        # the analysis below refuses a mesh; the warnings that need no height field first
        for warning in control_and_network_warnings(project, args.project.parent):
            print(warning.line(args.project), file=sys.stderr)
    result = plan_project(project, args.project.parent, cell_m=args.cell_m)
    if args.json:
        print(json.dumps(plan_summary(result), indent=1))
    else:
        print(format_plan(result, str(args.project)))
    if args.maps is not None:
        from designer.survey.maps import write_coverage_map, write_gsd_map

        args.maps.mkdir(parents=True, exist_ok=True)
        xy = np.array([s.C_world[:2] for s in result.stations])
        plan = project.trajectory.flight_plan
        area = None if plan is None else np.array(plan.area)
        cov = write_coverage_map(args.maps / "coverage.png", result.analysis.coverage,
                                 area=area, stations_xy=xy)
        gsd = write_gsd_map(args.maps / "gsd.png", result.analysis.coverage,
                            area=area, stations_xy=xy)
        if not args.json:
            print(f"maps: {cov}, {gsd}")
    if args.write_poses is not None:
        write_project(project_with_explicit_poses(result), args.write_poses)
        if not args.json:
            print(f"wrote {args.write_poses} with {len(result.stations)} explicit poses")
    return 0
