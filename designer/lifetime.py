"""How designer's processes end: SIGTERM and SIGHUP stop a command exactly as Ctrl-C
does, and every child process dies with its parent.

Batch systems and ``timeout`` send SIGTERM (then SIGKILL after a grace period), a closed
terminal SIGHUP. :func:`stop_on_termination_signals` turns both into the
``KeyboardInterrupt`` every command already handles (children stopped, finished work
kept, nothing half-written, a one-line message, exit status 130).
:func:`die_with_parent`, called first thing in every child designer starts (render
workers, study workers, figure processes), asks Linux to kill the child when its parent
exits — even by SIGKILL — so no worker is left rendering on its own (an orphan).
"""

from __future__ import annotations

import os
import signal
import sys

#: the signals that stop a command as Ctrl-C does
TERMINATION_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP")
                            if hasattr(signal, name))
_PR_SET_PDEATHSIG = 1
#: a program that starts ``designer`` commands (the GUI) sets this to its pid: the
#: command then dies with it (the variable is removed before the command's own children
#: start)
PARENT_PID_ENV = "DESIGNER_PARENT_PID"


def child_environment() -> dict[str, str]:
    """The variables a ``designer`` command started by this process needs to die with it."""
    return {PARENT_PID_ENV: str(os.getpid())}


def _interrupt(signum, _frame) -> None:
    raise KeyboardInterrupt(signal.Signals(signum).name)


def stop_on_termination_signals() -> None:
    """In the main thread of a command: SIGTERM and SIGHUP raise KeyboardInterrupt."""
    for sig in TERMINATION_SIGNALS:
        signal.signal(sig, _interrupt)


def die_with_parent(parent_pid: int | None = None,
                    signum: int = signal.SIGKILL) -> None:
    """Linux: the kernel sends this process ``signum`` (SIGKILL unless told: a program
    that must clean up on its way out, as the X server removing its lock file, asks for
    SIGTERM) when its parent exits. With ``parent_pid`` (the parent's pid as the parent
    knew it), a parent already gone before this call ends this process at once. Safe
    as a ``preexec_fn``. Elsewhere: nothing (the parent's own clean stop is all there
    is)."""
    if not sys.platform.startswith("linux"):
        return
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, int(signum), 0, 0, 0)
    except (OSError, AttributeError):
        return
    if parent_pid is not None and os.getppid() != parent_pid:
        os._exit(1)
