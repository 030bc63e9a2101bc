"""A virtual X display for headless runs (tests, ``designer gui --screenshot`` in CI).

Qt's offscreen platform cannot host a VTK OpenGL widget, so headless runs start Xvfb
(Debian package ``xvfb``) and use the ``xcb`` platform on it.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from pathlib import Path

SCREEN = "1600x1000x24"


class XvfbError(RuntimeError):
    pass


def start_xvfb(screen: str = SCREEN, first: int = 90, tries: int = 50
               ) -> tuple[subprocess.Popen, str]:
    """Start Xvfb on the first free display number from ``first``; (process, ":N")."""
    exe = shutil.which("Xvfb")
    if exe is None:
        raise XvfbError("no X display and no Xvfb: install the Debian package xvfb "
                        "(scripts/install-system-packages.sh) or set DISPLAY")
    for number in range(first, first + tries):
        if Path(f"/tmp/.X{number}-lock").exists() or Path(f"/tmp/.X11-unix/X{number}").exists():
            continue
        proc = subprocess.Popen([exe, f":{number}", "-screen", "0", screen, "-nolisten", "tcp"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                preexec_fn=_die_with_parent)
        for _ in range(100):
            if Path(f"/tmp/.X11-unix/X{number}").exists():
                return proc, f":{number}"
            if proc.poll() is not None:
                break
            time.sleep(0.05)
        if proc.poll() is None:
            proc.terminate()
            proc.wait(5)
    raise XvfbError("could not start Xvfb on any display")


def _die_with_parent() -> None:
    """In the child: ask Linux for SIGTERM when the parent exits, so a crash or a
    forgotten stop never leaves the X server running."""
    try:
        import ctypes
        import signal

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def stop_xvfb(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()


def ensure_display() -> subprocess.Popen | None:
    """Make sure Qt has an X display: start Xvfb when DISPLAY is unset. Returns the Xvfb
    process to stop afterwards, or None when a display was already there."""
    os.environ.setdefault("QT_QPA_PLATFORM", "xcb")
    if os.environ.get("DISPLAY"):
        return None
    proc, display = start_xvfb()
    os.environ["DISPLAY"] = display
    return proc
