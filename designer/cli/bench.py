"""``designer bench NAME``: run a benchmark and print its table of measured figures."""

from __future__ import annotations

import argparse
import importlib
import inspect
from pathlib import Path

BENCHMARKS = {
    "core": "designer.bench.core",
    "scene": "designer.bench.scene",
    "project-io": "designer.bench.project_io",
    "survey": "designer.bench.survey",
    "render": "designer.bench.render",
    "render-sizes": "designer.bench.render_sizes",
    "sun-steps": "designer.bench.sun_steps",
    "compare": "designer.bench.compare",
    "gui": "designer.bench.gui",
    "accuracy": "designer.bench.accuracy",
    "effects": "designer.bench.effects",
    "dense": "designer.bench.dense",
    "study": "designer.bench.study",
    "reconstruct": "designer.bench.reconstruct",
    "rolling-adjustment": "designer.bench.rolling_adjustment",
    "doming": "designer.bench.doming",
    "scale": "designer.bench.scale",
    "mapper": "designer.bench.mapper",
}


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "bench", help="run a benchmark and print a table of measured figures",
        description="Run a benchmark and print a table of measured figures.",
    )
    parser.add_argument("name", choices=sorted(BENCHMARKS), help="which benchmark")
    parser.add_argument("--repeats", type=int, default=3, help="repeats; the best is kept")
    parser.add_argument("--scale", type=float, default=1.0, help=argparse.SUPPRESS)
    parser.add_argument("--survey", type=Path, default=None, metavar="DIR",
                        help="reconstruct: an already rendered example survey (a folder "
                             "'designer render' wrote) instead of rendering it; mapper: "
                             "the rendered survey to map (required)")
    parser.add_argument("--image-size", choices=["small", "example"], default=None,
                        help="study: the base survey's small 640 x 480 camera, or the example "
                             "survey's camera at its 1368 x 912 px")
    parser.add_argument("--template", default=None, metavar="NAME",
                        help="study: the study template to run (gcp-count, or "
                             "example-processing: the example-size study, CPU seconds per "
                             "stage and run)")
    parser.add_argument("--images", type=int, default=None, metavar="N",
                        help="gui: open a survey of about N images (the survey-block "
                             "template scaled; 720 is the template itself)")
    parser.add_argument("--sizes", default=None, metavar="N,N,…",
                        help="scale: the block sizes to measure, in images (default "
                             "60,240,720)")
    parser.add_argument("--frames", type=int, default=None, metavar="N",
                        help="render-sizes: frames rendered per row (more take in more of "
                             "the frames that swap texture tiles)")
    parser.add_argument("--no-node-graph", dest="node_graph", action="store_false",
                        default=None,
                        help="render-sizes: leave out the node graph's rows")
    parser.add_argument("--texture-sources", default=None, metavar="S,S",
                        help="render-sizes: the grown terrains' texture sources, "
                             "'procedural' (the example's) and/or 'image' (an image file "
                             "holding the same texels)")
    parser.add_argument("--variants", action="store_true",
                        help="render: also the rows of the world's elements (sun over time, "
                             "moving objects, buildings, plants, clouds, rig, rolling shutter)")
    parser.set_defaults(func=run, interrupted_hint="the rows printed above were measured; "
                        "nothing else is kept")


def run(args) -> int:
    module = importlib.import_module(BENCHMARKS[args.name])
    options = {}
    if args.survey is not None:
        if "survey" not in inspect.signature(module.run).parameters:
            from designer.errors import DesignerError

            raise DesignerError(f"--survey: 'designer bench {args.name}' renders its own "
                                "survey; give --survey only to 'designer bench reconstruct' or "
                                "'mapper'")
        if not (args.survey / "manifest.json").is_file():
            from designer.errors import DesignerError

            raise DesignerError(f"--survey {args.survey}: no manifest.json there; give a "
                                "folder 'designer render' wrote")
        options["survey"] = args.survey
    if args.image_size is not None:
        if "image_size" not in inspect.signature(module.run).parameters:
            from designer.errors import DesignerError

            raise DesignerError(f"--image-size: only 'designer bench study' takes it, not "
                                f"'designer bench {args.name}'")
        options["image_size"] = args.image_size
    if args.template is not None:
        if "template" not in inspect.signature(module.run).parameters:
            from designer.errors import DesignerError

            raise DesignerError(f"--template: only 'designer bench study' takes it, not "
                                f"'designer bench {args.name}'")
        if args.template not in module.TEMPLATES:
            from designer.errors import DesignerError

            raise DesignerError(f"--template {args.template}: give one of "
                                f"{', '.join(module.TEMPLATES)}")
        options["template"] = args.template
    if args.variants:
        if "variants" not in inspect.signature(module.run).parameters:
            from designer.errors import DesignerError

            raise DesignerError(f"--variants: only 'designer bench render' takes it, not "
                                f"'designer bench {args.name}'")
        options["variants"] = True
    if args.images is not None:
        if "images" not in inspect.signature(module.run).parameters:
            from designer.errors import DesignerError

            raise DesignerError(f"--images: only 'designer bench gui' takes it, not "
                                f"'designer bench {args.name}'")
        if args.images < 1:
            from designer.errors import DesignerError

            raise DesignerError(f"--images {args.images}: give a number of images >= 1")
        options["images"] = args.images
    if args.sizes is not None:
        options["sizes"] = _sizes(args.sizes, args.name, module)
    options.update(_render_sizes_options(args, module))
    if "on_row" in inspect.signature(module.run).parameters:
        options["on_row"] = _live_rows(module)
    rows = module.run(repeats=args.repeats, scale=args.scale, **options)
    print(module.format_table(rows))
    return 0


def _render_sizes_options(args, module) -> dict:
    """``--frames``, ``--no-node-graph`` and ``--texture-sources`` as run() options of
    ``designer bench render-sizes`` (DesignerError for another bench or a bad value)."""
    from designer.errors import DesignerError

    given = {"frames": args.frames, "node_graph": args.node_graph,
             "sources": args.texture_sources}
    options = {k: v for k, v in given.items() if v is not None}
    flag = {"frames": "--frames", "node_graph": "--no-node-graph",
            "sources": "--texture-sources"}
    for key in options:
        if key not in inspect.signature(module.run).parameters:
            raise DesignerError(f"{flag[key]}: only 'designer bench render-sizes' takes it, "
                                f"not 'designer bench {args.name}'")
    if "frames" in options and options["frames"] < 1:
        raise DesignerError(f"--frames {args.frames}: give a number of frames >= 1")
    if "sources" in options:
        sources = tuple(v for v in args.texture_sources.replace(" ", "").split(",") if v)
        if not sources or set(sources) - {"procedural", "image"}:
            raise DesignerError(f"--texture-sources {args.texture_sources}: give "
                                "procedural, image or both, separated by a comma")
        options["sources"] = sources
    return options


def _sizes(text: str, name: str, module) -> tuple[int, ...]:
    """``--sizes 60,240,720`` as numbers of images (DesignerError says what is wrong)."""
    from designer.errors import DesignerError

    if "sizes" not in inspect.signature(module.run).parameters:
        raise DesignerError(f"--sizes: only 'designer bench scale' takes it, not "
                            f"'designer bench {name}'")
    try:
        sizes = tuple(int(v) for v in text.replace(" ", "").split(",") if v)
    except ValueError:
        sizes = ()
    if not sizes or min(sizes) < 4:
        raise DesignerError(f"--sizes {text}: give block sizes in images, at least 4 each, "
                            "separated by commas (e.g. 60,240,720)")
    return sizes


def _live_rows(module):
    """Print each row on standard error as soon as it is measured (a run cut short keeps
    its figures); the whole table follows on standard output at the end."""
    import sys

    printed = [False]

    def on_row(row: dict) -> None:
        if hasattr(module, "format_row"):
            if not printed[0] and hasattr(module, "live_header"):
                print(module.live_header(), file=sys.stderr, flush=True)
            printed[0] = True
            print(module.format_row(row), file=sys.stderr, flush=True)

    return on_row
