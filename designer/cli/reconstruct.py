"""``designer reconstruct OUT``: COLMAP (pycolmap) on a rendered survey, georeferenced by GCPs."""

from __future__ import annotations

from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "reconstruct", help="reconstruct a rendered survey with COLMAP (pycolmap)",
        description=(
            "Run SIFT features and matching on a rendered survey, then triangulate with the "
            "true poses (known-poses, the ideal case) or run incremental SfM and georeference "
            "it with the control GCPs (free). Writes the sparse model, a PLY cloud, GCP "
            "residuals and summary.json. Dense stereo needs CUDA and is skipped on the CPU."),
    )
    parser.add_argument("survey", type=Path, help="output folder of 'designer render'")
    parser.add_argument("-o", "--output", type=Path, default=None,
                        help="reconstruction folder (default: SURVEY/reconstruction-MODE)")
    parser.add_argument("--mode", choices=["known-poses", "free"], default="known-poses")
    parser.add_argument("--max-features", type=int, default=8192,
                        help="SIFT features per image (default 8192)")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.sfm.reconstruct import reconstruct

    out = args.output or args.survey / f"reconstruction-{args.mode}"
    result = reconstruct(args.survey, out, mode=args.mode, max_features=args.max_features)
    print(f"{out}: {result.n_registered}/{result.n_images} images registered, "
          f"{result.n_points} points; cloud {result.cloud_ply}; GCP residuals "
          f"{result.gcp_residuals_csv}")
    return 0
