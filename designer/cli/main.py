"""Entry point of the ``designer`` command.

Each sub-command lives in its own module under ``designer.cli`` with a
``register(subparsers)`` function that adds its parser and sets ``func`` to a
callable ``func(args) -> int``. Command modules import their heavy dependencies
inside ``func`` so that ``designer --help`` stays fast.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading

from designer import __version__
from designer.errors import DesignerError

#: modules that provide sub-commands, in the order ``--help`` lists them
COMMAND_MODULES = [
    "designer.cli.new",
    "designer.cli.check",
    "designer.cli.plan",
    "designer.cli.export_flight",
    "designer.cli.import_flight",
    "designer.cli.render",
    "designer.cli.check_output",
    "designer.cli.reconstruct",
    "designer.cli.compare",
    "designer.cli.study",
    "designer.cli.validate",
    "designer.cli.gui",
    "designer.cli.demo",
    "designer.cli.bench",
    "designer.cli.warmup",
]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="designer",
        description=(
            "Design, render and evaluate repeatable virtual surveys for "
            "Structure-from-Motion accuracy experiments."
        ),
    )
    parser.add_argument("--version", action="version", version=f"designer {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    return parser


def listen_to_sigint() -> None:
    """Stop cleanly on SIGINT even when started ignoring it.

    A non-interactive shell starts background jobs (``cmd &``: scripts, cluster job
    wrappers, a GUI launched that way) with SIGINT ignored, and Python then keeps it
    ignored: Ctrl-C sent on purpose (``kill -INT``, the GUI's Cancel) would do nothing
    and a render would run to its end. designer always turns SIGINT into its clean stop.
    """
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def main(argv: list[str] | None = None) -> int:
    listen_to_sigint()
    if threading.current_thread() is threading.main_thread():
        from designer.lifetime import PARENT_PID_ENV, die_with_parent, stop_on_termination_signals

        stop_on_termination_signals()
        parent = os.environ.pop(PARENT_PID_ENV, None)  # not passed on to our children
        if parent and parent.isdigit():  # started by the GUI: end with it
            die_with_parent(int(parent))
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except DesignerError as error:
        print(f"designer: error: {error}", file=sys.stderr)
        return error.exit_code
    except KeyboardInterrupt as stop:  # Ctrl-C, SIGTERM, SIGHUP
        why = f" by {stop.args[0]}" if stop.args and isinstance(stop.args[0], str) else ""
        hint = getattr(args, "interrupted_hint", None)
        print(f"designer: interrupted{why}" + (f": {hint}" if hint else ""), file=sys.stderr)
        return 130


#: set by a command whose every product is written, closed and reported (see :func:`entry`)
_exit_at_once = False
_as_program = False


def running_as_program() -> bool:
    """True in the ``designer`` program (:func:`entry`), False when :func:`main` is
    called in-process (tests, scripts)."""
    return _as_program


def exit_at_once_when_done() -> None:
    """Let :func:`entry` end the process without Python's teardown once this command
    returns. For commands whose output is complete when they return: finalizers and
    atexit handlers do not run (none of designer's own writes depends on them — every
    file is written atomically and closed before the command returns)."""
    global _exit_at_once
    _exit_at_once = True


def entry() -> None:
    """The ``designer`` program: :func:`main`, then exit with its code.

    Tearing down an interpreter that has loaded matplotlib, rasterio and large arrays
    takes 0.1–0.3 s of freeing what the operating system frees at once;
    a command that asked for it (``designer compare``) skips that with ``os._exit``
    after flushing its output. Called in-process (tests, scripts), :func:`main` returns
    normally and nothing is skipped.
    """
    global _as_program
    _as_program = True
    try:
        code = main()
        if _exit_at_once:
            sys.stdout.flush()
    except BrokenPipeError:
        # the reader went away (``designer plan P.xml | head``): stop quietly, as other
        # command-line tools do, without a traceback or a second error at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        sys.exit(1)
    if _exit_at_once:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)


if __name__ == "__main__":  # pragma: no cover
    entry()
