"""``designer validate projection|psf|texture``: check that Cycles renders what the model says.

Each experiment writes DIR/report.md (with PNG figures beside it) and DIR/summary.json,
prints a summary and exits 1 when a criterion fails (docs/validation.md).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

FULL_IMAGES = 500


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "validate", help="validation experiments: projection, point-spread function, texture",
        description=(
            "Render validation scenes with Cycles and check them against designer's camera "
            "model. Each writes DIR/report.md with figures and DIR/summary.json, prints a "
            "summary and exits 1 if a criterion fails. See docs/validation.md."),
    )
    sub = parser.add_subparsers(dest="experiment", metavar="EXPERIMENT", required=True)
    projection = sub.add_parser(
        "projection", help="checkerboard corners in a 10 m cube against the projection",
        description=(
            "Render checkerboard corners inside a 10 m cube from random poses with five "
            "interior orientations, detect them (Harris + sub-pixel refinement) and compare "
            "with the projection: mean, spread, correlations, and a variance test against "
            "the detector's own error on exact synthetic images."))
    _common(projection, "validation-projection")
    projection.add_argument("--images", type=int, default=25,
                            help="number of images (default 25; --full: 500)")
    projection.add_argument("--full", action="store_true",
                            help=f"the original study's {FULL_IMAGES} images")
    projection.add_argument("--size", default="960x640", metavar="WxH",
                            help="image size in pixels (default 960x640)")
    projection.add_argument("--baseline", type=int, default=1000,
                            help="synthetic images for the detector baseline (default 1000)")
    projection.add_argument("--seed", type=int, default=0, help="random seed of the poses")
    # A deliberate camera-mapping fault (px, right and down), to show the validation fails.
    projection.add_argument("--inject-pp-error", default=None, help=argparse.SUPPRESS)
    projection.set_defaults(func=run_projection)
    psf = sub.add_parser("psf", help="a sphere inside one pixel's cone lights only that pixel",
                         description="Point-spread function: render a sphere smaller than one "
                                     "pixel's viewing cone with and without antialiasing.")
    _common(psf, "validation-psf")
    psf.set_defaults(func=run_psf)
    texture = sub.add_parser("texture", help="a 100 px texel stays sharp and in place",
                             description="Texture resolution: a 10 cm texel seen as 100 x 100 px, "
                                         "'Closest' against 'Linear' interpolation.")
    _common(texture, "validation-texture")
    texture.set_defaults(func=run_texture)


def _common(parser, default_dir: str) -> None:
    parser.add_argument("-o", "--output", type=Path, default=Path(default_dir),
                        help=f"report folder (default: {default_dir})")
    parser.add_argument("--quality", choices=["draft", "survey", "metrology"],
                        default="metrology",
                        help="render quality preset (default metrology; docs/validation.md)")
    parser.add_argument("--workers", type=int, default=None, help="render worker processes")


def _size(text: str) -> tuple[int, int]:
    from designer.errors import DesignerError

    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise DesignerError(f"--size {text!r}: give WIDTHxHEIGHT in pixels, e.g. 960x640") from None
    if w < 64 or h < 64:
        raise DesignerError(f"--size {text}: images must be at least 64 x 64 px")
    return w, h


def _finish(summary: dict, out: Path, t0: float) -> int:
    print(f"{summary['experiment']}: {'PASSED' if summary['passed'] else 'FAILED'} "
          f"in {time.perf_counter() - t0:.0f} s")
    for c in summary["criteria"]:
        c = c if isinstance(c, dict) else c.to_dict()
        mark = "pass" if c["passed"] else "FAIL"
        print(f"  [{mark}] {c['name']}: {c['value']} (limit {c['limit']})")
    print(f"report: {out / 'report.md'}; figures and numbers: {out / 'summary.json'}")
    return 0 if summary["passed"] else 1


def run_projection(args) -> int:
    from designer.errors import DesignerError
    from designer.experiments.projection import ProjectionConfig, run_projection
    from designer.experiments.projection_report import write_projection_report
    from designer.experiments.settings import quality

    t0 = time.perf_counter()
    n = FULL_IMAGES if args.full else args.images
    if n < 5:
        raise DesignerError(f"--images {n}: give at least 5 (one per interior orientation)")
    if args.baseline < 100:
        raise DesignerError(f"--baseline {args.baseline}: give at least 100 synthetic images")
    pp_error = (0.0, 0.0)
    if args.inject_pp_error:
        pp_error = tuple(float(x) for x in args.inject_pp_error.split(","))
    config = ProjectionConfig(n_images=n, size_px=_size(args.size),
                              settings=quality(args.quality), seed=args.seed,
                              n_baseline=args.baseline, render_pp_error_px=pp_error,
                              workers=args.workers)
    result = run_projection(config, args.output / "renders",
                            progress=lambda msg: print(msg, file=sys.stderr, flush=True))
    summary = write_projection_report(result, args.output)
    o = result.overall
    print(f"{int(result.corners.found.sum())} corners in {n} images: "
          f"dx {o['dx'].mean_px:+.4f} ± {o['dx'].std_px:.4f} px, "
          f"dy {o['dy'].mean_px:+.4f} ± {o['dy'].std_px:.4f} px, "
          f"dr {o['dr'].mean_px:+.4f} ± {o['dr'].std_px:.4f} px (mean ± std); detector alone "
          f"{result.variance.std_b_px:.4f} px, Levene p = {result.variance.levene_p:.3g}")
    return _finish(summary, args.output, t0)


def run_psf(args) -> int:
    from designer.experiments.psf import PSFConfig, validate_psf
    from designer.experiments.settings import quality

    t0 = time.perf_counter()
    summary = validate_psf(PSFConfig(settings=quality(args.quality), workers=args.workers),
                           args.output)
    for r in summary["renders"]:
        print(f"  {r['name']}: centre {r['centre']:.4f}, 8 neighbours {r['neighbours']:.4g}, "
              f"all others {r['elsewhere']:.4g}")
    return _finish(summary, args.output, t0)


def run_texture(args) -> int:
    from designer.experiments.settings import quality
    from designer.experiments.texture import TextureConfig, validate_texture

    t0 = time.perf_counter()
    summary = validate_texture(TextureConfig(settings=quality(args.quality),
                                             workers=args.workers), args.output)
    n = summary["numbers"]
    print(f"  Closest: {n['point_impure']} impure pixels without antialiasing, "
          f"{n['aa_impure_off_edges']} off the edges with it (edge error max "
          f"{n['aa_edge_error_max']:.3f} px); Linear: {n['linear_impure']} of {n['pixels']} "
          "pixels blended")
    return _finish(summary, args.output, t0)
