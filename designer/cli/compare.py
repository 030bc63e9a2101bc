"""``designer compare CLOUD MESH_OR_PROJECT -o DIR``: accuracy of a cloud against the truth."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "compare", help="compare a reconstruction with the true surface, GCPs and cameras",
        description=(
            "Signed distances from every point of CLOUD to the true mesh (exact, float64, "
            "positive above the terrain), their statistics (mean, std, RMSE, median, NMAD, "
            "68.3/95 %% quantiles, tolerance shares), a histogram and an error map; with "
            "--truth also GCP/check-point and camera pose errors. Writes DIR/distances.ply, "
            "DIR/summary.json, DIR/report.md and DIR/report.html, and prints a summary."),
    )
    parser.add_argument("cloud", type=Path,
                        help="point cloud: PLY, LAS/LAZ, XYZ/CSV/TXT, or a COLMAP model folder")
    parser.add_argument("reference", type=Path, metavar="MESH_OR_PROJECT",
                        help="true mesh (PLY/OBJ/STL, world coordinates) or project XML")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    parser.add_argument("--offset", type=float, nargs=3, metavar=("E", "N", "H"),
                        help="add this to the cloud's (and its COLMAP model's) coordinates, "
                             "in float64 after reading (for clouds written in a local frame)")
    parser.add_argument("--allow-float32", action="store_true",
                        help="compare a cloud whose stored coordinates are coarser than 1 mm "
                             "(float32 at UTM size, a coarse LAS scale) instead of refusing "
                             "it; the spacing is recorded in summary.json")
    parser.add_argument("--columns", nargs=3, metavar=("X", "Y", "Z"),
                        help="text clouds: the x, y, z columns, by header name or 0-based number")
    parser.add_argument("--max-distance", type=float, metavar="M",
                        help="leave out points farther than M metres from the mesh")
    parser.add_argument("--tolerance", type=float, nargs="+", metavar="M",
                        help="tolerances (m) whose share of |d| is reported "
                             "(default 0.01 0.02 0.05 0.1 0.2)")
    parser.add_argument("--cell-m", type=float, metavar="M", help="error-map cell size (m)")
    parser.add_argument("--no-targets", action="store_true",
                        help="project XML: compare with the terrain alone, not the GCP plates")
    parser.add_argument("--surface", choices=("dtm", "dsm"),
                        help="with a project XML as the reference: compare with the bare "
                             "earth (dtm) or the surface with objects, buildings and "
                             "vegetation (dsm, the default)")
    parser.add_argument("--at-time", type=float, metavar="T",
                        help="project XML: include its moving objects posed at T seconds "
                             "after take-off and its plants as they sway then (default: "
                             "the static ground without moving objects, plants upright)")
    parser.add_argument("--truth", type=Path, metavar="DIR",
                        help="a rendered survey folder (or its ground-truth/): adds GCP and "
                             "camera errors")
    parser.add_argument("--gcps", type=Path, metavar="CSV",
                        help="estimated GCP coordinates (id, X, Y, Z); default: triangulated "
                             "from the COLMAP model and the true GCP observations")
    parser.add_argument("--cameras", type=Path, metavar="PATH",
                        help="estimated cameras: COLMAP model, omega-phi-kappa table or ODM "
                             "shots.geojson; default: CLOUD when it is a COLMAP model")
    parser.add_argument("--no-align", action="store_true",
                        help="camera errors without the 7-parameter similarity alignment")
    parser.add_argument("--area", choices=("aoi", "all"), default="aoi",
                        help="points the statistics cover: 'aoi' (default) those over a "
                             "project's area of interest, its declared terrain extent; "
                             "'all' every point (the truth covers the surroundings the "
                             "images saw too); a mesh file has no area of interest")
    parser.add_argument("--json", action="store_true", help="print summary.json instead")
    parser.set_defaults(func=run, interrupted_hint="nothing was written; run the same "
                        "command again")


def _project_origin(reference: Path) -> tuple[float, float, float] | None:
    """The origin (E0, N0, H0) of a project XML reference: the local frame to suggest for
    a cloud stored too coarsely; None for a mesh file or an unreadable project."""
    from designer.errors import DesignerError

    if reference.suffix.lower() != ".xml" or not reference.is_file():
        return None
    from designer.project import load_project

    try:
        origin = load_project(reference).origin
    except DesignerError:
        return None
    return origin.E0, origin.N0, origin.H0


def _truth_folder(path: Path) -> Path:
    from designer.errors import DesignerError

    for folder in (path / "ground-truth", path):
        if (folder / "gcp_truth.csv").is_file() or (folder / "camera_poses_opk.csv").is_file():
            return folder
    raise DesignerError(f"{path} holds no ground truth (gcp_truth.csv or camera_poses_opk.csv, "
                        "directly or in ground-truth/)")


def extra_errors(args) -> tuple[dict | None, dict | None]:
    """(GCP errors, camera errors) requested by ``--truth``/``--gcps``/``--cameras``."""
    from designer.errors import DesignerError

    if args.truth is None:
        if args.gcps or args.cameras:
            raise DesignerError("--gcps and --cameras need --truth (the rendered survey folder)")
        return None, None
    from designer.evaluate import (
        camera_pose_errors,
        gcp_errors,
        read_camera_poses,
        read_gcp_estimates_csv,
        triangulate_gcps,
    )
    from designer.export.colmap_read import model_files
    from designer.export.tables import (
        read_gcp_observations_csv,
        read_gcp_truth_csv,
        read_opk_csv,
    )

    truth = _truth_folder(args.truth)
    model = args.cameras if args.cameras is not None else args.cloud
    is_model = model.is_dir() and model_files(model) is not None
    gcps = cameras = None
    if (truth / "gcp_truth.csv").is_file():
        true_gcps = read_gcp_truth_csv(truth / "gcp_truth.csv")
        estimated = None
        if args.gcps is not None:
            estimated = read_gcp_estimates_csv(args.gcps)
        elif is_model and (truth / "gcp_observations.csv").is_file():
            estimated = triangulate_gcps(model, read_gcp_observations_csv(
                truth / "gcp_observations.csv"), offset_world=args.offset)
        if estimated:
            gcps = gcp_errors(estimated, true_gcps)
    if (truth / "camera_poses_opk.csv").is_file() and (args.cameras is not None or is_model):
        offset = args.offset if is_model else None
        cameras = camera_pose_errors(read_camera_poses(model, offset_world=offset),
                                     read_opk_csv(truth / "camera_poses_opk.csv"),
                                     align=not args.no_align)
    return gcps, cameras


def run(args) -> int:
    from designer.cli.main import exit_at_once_when_done, running_as_program
    # before numpy loads OpenBLAS (nothing has imported numpy yet in a `designer compare`
    # process; called in-process, this changes nothing): see _tune_process
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    from designer.evaluate import figures

    _tune_process()
    # Start what does not depend on the inputs first: the figure writer imports
    # matplotlib while the inputs are read and the kernels compute. The program draws
    # its two figures in two processes at once (forked now, while it has one thread).
    figures.prestart(processes=running_as_program())
    try:
        code = _compare(args)
    finally:
        figures.discard_prestarted()
    # every product is written and closed: skip the interpreter's slow teardown
    exit_at_once_when_done()
    return code


def _tune_process() -> None:
    """Settings for one comparison process, each measured with ``designer bench compare``.

    * This thread hands the inputs to the kernels in many short steps while other
      threads hold the GIL (the figure thread's matplotlib import when the figures are
      drawn in-process; the PLY writer and the error map's grid at the end): a 0.5 ms
      switch interval instead of 5 ms lets each step start without waiting (-0.05 s
      with the figure thread, -0.02 s with the figure processes).
    * OpenBLAS (set before numpy loads, in :func:`run`): the comparison's BLAS calls
      are small (matplotlib's transforms), yet after each one OpenBLAS's worker threads
      spin on ``sched_yield`` for a while, taking CPU time the kernels need (7 % of the
      process's CPU time, by ``perf``): one BLAS thread.
    * numpy asks the kernel for transparent huge pages for large arrays; where the
      system compacts memory to find them (THP defrag "madvise", the default of many
      distributions) the first touch of the mesh index's few hundred MB costs more in
      page faults than the huge pages save (-0.1 to -0.3 s here).
    """
    import numpy as np

    sys.setswitchinterval(0.0005)
    set_madvise = getattr(np.core.multiarray, "_set_madvise_hugepage", None)
    if set_madvise is not None:
        set_madvise(False)


def _compare(args) -> int:
    from designer.errors import DesignerError
    from designer.evaluate.compare import (
        coarse_warnings,
        compare_cloud,
        crop_to_area,
        reference_mesh,
    )
    from designer.evaluate.point_clouds import read_point_cloud
    from designer.evaluate.report import format_summary
    from designer.evaluate.statistics import DEFAULT_TOLERANCES_M

    for name in ("max_distance", "cell_m"):
        value = getattr(args, name)
        if value is not None and not value > 0:
            raise DesignerError(f"--{name.replace('_', '-')} {value}: give a value > 0")
    tolerances = tuple(args.tolerance) if args.tolerance else DEFAULT_TOLERANCES_M
    if any(not t > 0 for t in tolerances):
        raise DesignerError("--tolerance values must be > 0")
    if not args.reference.exists():
        raise DesignerError(f"reference {args.reference} does not exist")
    cloud = read_point_cloud(args.cloud, offset=args.offset,
                             columns=tuple(args.columns) if args.columns else None,
                             allow_coarse=args.allow_float32,
                             offset_hint=lambda: _project_origin(args.reference))
    for warning in coarse_warnings(cloud):
        print(f"warning: {args.cloud}: {warning}", file=sys.stderr)
    if args.surface is not None and args.reference.suffix.lower() != ".xml":
        raise DesignerError(f"--surface {args.surface}: needs a project XML as the reference, "
                            f"not {args.reference.name} (a mesh file is its own surface)")
    if args.at_time is not None and args.reference.suffix.lower() != ".xml":
        raise DesignerError(f"--at-time {args.at_time}: needs a project XML as the reference, "
                            f"not {args.reference.name}")
    if args.at_time is not None and not (args.at_time >= 0 and args.at_time < 1e7):
        raise DesignerError(f"--at-time {args.at_time}: give seconds after take-off, >= 0")
    growth = None
    if args.reference.suffix.lower() == ".xml":
        # the truth covers the surroundings the renderer drew around the terrain
        from designer.project import load_project
        from designer.survey.surroundings import project_surroundings

        growth = project_surroundings(load_project(args.reference), args.reference.parent)[0]
    mesh = reference_mesh(args.reference, with_targets=not args.no_targets,
                          at_time_s=args.at_time, surface=args.surface or "dsm", growth=growth)
    cloud, area = crop_to_area(cloud, mesh, args.area)
    gcps, cameras = extra_errors(args)
    summary = compare_cloud(cloud, mesh, args.output, max_distance=args.max_distance,
                            tolerances=tolerances, cell_m=args.cell_m, gcps=gcps,
                            cameras=cameras, offset=args.offset, area=area)
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        print(format_summary(summary))
        print(f"wrote {args.output / 'distances.ply'}, {args.output / 'summary.json'}, "
              f"{args.output / 'report.html'}")
    return 0
