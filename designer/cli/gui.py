"""``designer gui [PROJECT.xml] [--screenshot FILE.png]``: the desktop designer.

Qt and VTK are imported inside ``run`` only, so the rest of the command line works
without them.
"""

from __future__ import annotations

from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "gui", help="open the desktop designer (PySide6 + pyvista)",
        description=(
            "Design a survey with the mouse: terrain, texture, GCPs, camera, flight, "
            "effects, render and results in one window. With --screenshot the window "
            "opens the project, renders once, saves a PNG and exits (starting a virtual "
            "X display with Xvfb when there is no DISPLAY)."),
    )
    parser.add_argument("project", type=Path, nargs="?", metavar="PROJECT.xml",
                        help="project to open")
    parser.add_argument("--screenshot", type=Path, metavar="FILE.png",
                        help="save a screenshot of the window and exit")
    parser.add_argument("--panel", default=None,
                        help="with --screenshot: the panel to bring to the front, e.g. Flight")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.errors import DesignerError

    try:
        from designer.gui.app import run as run_gui
    except ImportError as error:
        raise DesignerError(f"the GUI needs PySide6, pyvista and pyvistaqt ({error}); "
                            "install designer[gui]") from None
    return run_gui(args.project, args.screenshot, args.panel)
