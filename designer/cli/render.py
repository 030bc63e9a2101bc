"""``designer render PROJECT.xml -o OUT``: render a survey with local worker processes."""

from __future__ import annotations

import json
import sys
from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "render", help="render a project's images and write its ground truth",
        description=(
            "Render every image of a project with Blender/Cycles in local worker processes, "
            "into OUT/images/ (nothing else is written there), then the ground truth "
            "(COLMAP, OpenDroneMap, Metashape, OPK, GCP tables) into OUT/ground-truth/, "
            "OUT/manifest.json and OUT/README.txt (which file each program takes). Images "
            "appear only when complete; Ctrl-C stops cleanly and --resume continues where a "
            "run stopped (and moves the images of a folder rendered before images/ existed "
            "into it)."),
    )
    parser.add_argument("project", type=Path, help="project XML file")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    parser.add_argument("--workers", type=int, default=None,
                        help="worker processes (default: the project's, else fitted to the cores)")
    parser.add_argument("--frames", default=None,
                        help="0-based frames to render, e.g. 0-99,120 (default: all)")
    parser.add_argument("--quality", choices=["draft", "survey", "metrology"], default=None,
                        help="samples preset: draft 4, survey 16 samples per pixel, "
                             "metrology adaptive sampling up to 64 (default: the project's "
                             "render settings); costs and accuracy in docs/validation.md")
    parser.add_argument("--resume", action="store_true",
                        help="skip images that are already complete and readable")
    parser.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                        help="render on an existing Dask cluster; OUT must be on storage "
                             "every worker sees under the same path")
    parser.add_argument("--colmap-offset", default="local", metavar="local|none|E,N,H",
                        help="frame of the COLMAP ground truth: 'local' (default) = world "
                             "minus the mean camera centre rounded to whole metres, so "
                             "COLMAP's float32 dense stage keeps 0.1 mm; 'none' = world "
                             "coordinates; or E,N,H in metres. The offset is written to "
                             "ground-truth/colmap/offset.json and the manifest")
    parser.add_argument("--progress", choices=["bar", "json", "none"], default=None,
                        help="progress display: a bar on a terminal, JSON lines for programs")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.errors import DesignerError
    from designer.render.pipeline import render_project
    from designer.render.void_share import void_warning

    if args.workers is not None and args.workers < 1:
        raise DesignerError(f"--workers {args.workers}: give at least 1 worker")
    from designer.export.colmap import colmap_offset_world

    colmap_offset_world(args.colmap_offset, [])  # a bad value stops here, before any work
    _refuse_low_stations(args.project)
    mode = args.progress or ("bar" if sys.stderr.isatty() else "none")
    reporter = ProgressPrinter(mode)
    try:
        summary = render_project(args.project, args.output, workers=args.workers,
                                 frames=args.frames, quality=args.quality,
                                 resume=args.resume, progress=reporter,
                                 scheduler=args.scheduler, colmap_offset=args.colmap_offset)
    except KeyboardInterrupt as stop:  # Ctrl-C, SIGTERM, SIGHUP: the workers are stopped
        from designer.render.pipeline import continue_hint

        images = args.output / "images"
        why = f" by {stop.args[0]}" if stop.args else ""
        kept = getattr(stop, "kept", None)
        if kept is not None:  # counted against the project: up to date apart from stale
            said = f"in {images}: {kept.text(args.resume)}"
        else:  # stopped while the job was prepared: nothing was rendered
            said = f"no image rendered; {continue_hint(args.resume)}"
        print(f"designer: interrupted{why}: {said}", file=sys.stderr)
        return 130
    finally:
        reporter.close()
    report = summary.report
    n = len(report.rendered)
    print(f"{args.output}: {n} images rendered, {len(report.skipped)} already complete "
          f"and up to date, {summary.times.text()}; images in "
          f"{args.output / 'images'}, ground truth in {args.output / 'ground-truth'}, "
          f"which file each program takes in {args.output / 'README.txt'}")
    if summary.stale:
        from designer.render.check_output import count_reasons

        print(f"{len(summary.stale)} of the rendered images replaced images made from other "
              f"inputs: {count_reasons(summary.stale)}")
    from designer.render.job_spec import SKY_RGB

    # with a sky (images that look towards the horizon) the background is the sky, seen
    # above the horizon: not void
    sky = tuple(summary.prepared.job.background_rgb) == SKY_RGB
    warning = void_warning(summary.void) if summary.void is not None and not sky else None
    if warning is not None:  # the last line: images that are partly empty background
        print(f"designer: warning: {warning}", file=sys.stderr)
    return 0


def _refuse_low_stations(path: Path) -> None:
    """Stop, as ``designer check`` and ``plan`` do, before anything is rendered when
    camera stations are under the ground: their images would be taken from inside it."""
    from designer.checks.project_checks import refuse_low_stations
    from designer.project.load import load_project_located

    project, smap = load_project_located(path)
    refuse_low_stations(project, smap, path)


class ProgressPrinter:
    """Turns worker events into a progress bar (stderr) or JSON lines (stdout)."""

    def __init__(self, mode: str) -> None:
        self.mode = mode
        self.bar = None

    def __call__(self, event: dict) -> None:
        if self.mode == "json":
            print(json.dumps(event), flush=True)
        elif self.mode == "bar" and event["event"] in ("frame_done", "frame_skipped"):
            if self.bar is None:
                from tqdm import tqdm

                self.bar = tqdm(unit="img", file=sys.stderr, desc="rendering")
            self.bar.update(1)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
