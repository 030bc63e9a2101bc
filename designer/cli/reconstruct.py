"""``designer reconstruct OUT``: photogrammetric processing of a rendered survey (pycolmap)."""

from __future__ import annotations

from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "reconstruct", help="reconstruct a rendered survey with COLMAP (pycolmap)",
        description=(
            "Process a rendered survey as survey software does: SIFT features and matching, "
            "then triangulation with the true poses (known-poses, the ideal case) or "
            "incremental SfM and a bundle adjustment with the project's <processing> "
            "settings (free): self-calibration, GCPs marked in the images with a marking "
            "error, GNSS/RTK camera positions. The options override <processing>. Writes "
            "DIR/summary.json (control and check RMSE, intrinsics vs truth, camera errors, "
            "sigma0), DIR/sparse.ply (doubles), DIR/gcp_residuals.csv and DIR/model/."),
    )
    parser.add_argument("survey", type=Path, help="output folder of 'designer render'")
    parser.add_argument("-o", "--output", type=Path, default=None,
                        help="reconstruction folder (default: SURVEY/reconstruction-MODE)")
    parser.add_argument("--mode", choices=["known-poses", "free"], default="known-poses")
    parser.add_argument("--project", type=Path, default=None,
                        help="project file whose <processing> to use (default: the one "
                             "named in SURVEY/manifest.json)")
    parser.add_argument("--calibration",
                        choices=["fixed", "focal", "focal-principal-point", "radial", "full"],
                        help="interior parameters estimated in the adjustment")
    parser.add_argument("--rolling-shutter", choices=["none", "compensate"],
                        help="rolling-shutter images: none (processed as global shutter) or "
                             "compensate (the final adjustment estimates each image's "
                             "velocity during the readout; needs --mode free)")
    parser.add_argument("--gcps", choices=["none", "similarity", "bundle"],
                        help="how control points enter")
    parser.add_argument("--marking-sigma-px", type=float, metavar="S",
                        help="sigma of the marking error of target image positions, px")
    parser.add_argument("--control", metavar="IDS|K",
                        help="control points: comma-separated GCP ids, or a count K "
                             "(spread by --control-spread)")
    parser.add_argument("--control-spread", choices=["even", "random"], default=None)
    parser.add_argument("--position-prior", choices=["none", "gnss", "rtk"],
                        help="camera positions as weighted priors")
    parser.add_argument("--pairs", choices=["footprint", "position", "exhaustive"],
                        help="which image pairs are matched")
    parser.add_argument("--min-track-length", type=int, help="tie points need this many images")
    parser.add_argument("--dense", choices=["none", "cpu", "auto"],
                        help="dense matching: OpenCV semi-global matching + COLMAP fusion on "
                             "the CPU (auto = the best matcher this machine runs: cpu); writes "
                             "dense.ply, dense.laz, dsm.tif, dod.tif, dod.png")
    parser.add_argument("--dense-max-image-px", type=int, default=None, metavar="PX",
                        help="longer image side for dense matching (default: full size)")
    parser.add_argument("--mapper", choices=["incremental", "global"], default=None,
                        help="structure from motion (--mode free): incremental (COLMAP's, "
                             "the default) or global (GLOMAP's rotation averaging and global "
                             "positioning); docs/processing.md compares them")
    parser.add_argument("--global-adjustment-growth", type=float, default=None,
                        metavar="FACTOR",
                        help="the incremental mapper adjusts the whole model again once it "
                             "has grown by FACTOR (default 1.1, COLMAP's; 1.4 takes about a "
                             "third less mapper time on blocks of hundreds of images)")
    parser.add_argument("--max-features", type=int, default=None,
                        help="SIFT features per image (default 8192)")
    parser.add_argument("--sift-scale", choices=["doubled", "original", "half"], default=None,
                        help="the image size SIFT's first octave works on: doubled (COLMAP's "
                             "default), original (about a quarter of the extraction work) "
                             "or half")
    parser.add_argument("--feature-cache", type=Path, default=None, metavar="DIR",
                        help="keep features and matches in DIR and reuse them when the same "
                             "images are reconstructed again (other settings may differ)")
    parser.set_defaults(func=run, interrupted_hint="this reconstruction is not kept; run "
                        "the same command again")


def run(args) -> int:
    from designer.sfm.reconstruct import reconstruct
    from designer.sfm.settings import resolve_processing

    ids = count = None
    if args.control:
        if args.control.isdigit():
            count = int(args.control)
        else:
            ids = tuple(i.strip() for i in args.control.split(",") if i.strip())
    processing = resolve_processing(
        args.survey, args.project, calibration=args.calibration, gcps=args.gcps,
        marking_sigma_px=args.marking_sigma_px, position_prior=args.position_prior,
        dense=args.dense, max_features=args.max_features, sift_scale=args.sift_scale,
        pairs=args.pairs,
        min_track_length=args.min_track_length, control_ids=ids, control_count=count,
        control_spread=args.control_spread, rolling_shutter=args.rolling_shutter,
        mapper=args.mapper, global_adjustment_growth=args.global_adjustment_growth)
    out = args.output or args.survey / f"reconstruction-{args.mode}"
    if args.dense_max_image_px is not None and args.dense_max_image_px < 64:
        from designer.errors import DesignerError

        raise DesignerError(f"--dense-max-image-px {args.dense_max_image_px}: give at least "
                            "64 px")
    result = reconstruct(args.survey, out, mode=args.mode, processing=processing,
                         project_path=args.project,
                         dense_max_image_px=args.dense_max_image_px,
                         feature_cache=args.feature_cache)
    s = result.summary
    line = (f"{out}: {result.n_registered}/{result.n_images} images registered, "
            f"{result.n_points} points")
    for role in ("control", "check"):
        if s[role].get("n"):
            line += (f"; {role} RMSE X/Y/Z {s[role]['rmse_x_m']:.3f}/{s[role]['rmse_y_m']:.3f}/"
                     f"{s[role]['rmse_z_m']:.3f} m")
    print(line)
    print(f"cloud {out / 'sparse.ply'}; GCP residuals {result.gcp_residuals_csv}; "
          f"summary {out / 'summary.json'}")
    dense = s.get("dense") or {}
    if dense.get("status") == "ok":
        dome = dense.get("dome_amplitude_m")
        print(f"dense cloud {out / 'dense.ply'} ({dense['points']} points, {dense['matcher']}); "
              f"DoD {out / 'dod.tif'}; dome amplitude "
              + (f"{dome:+.3f} m over {dense.get('dome_area', 'the whole DoD')}"
                 if dome is not None else "none"))
    return 0
