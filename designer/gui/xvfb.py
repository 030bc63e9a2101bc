"""A virtual X display for headless runs (tests, ``designer gui --screenshot`` in CI).

Qt's offscreen platform cannot host a VTK OpenGL widget, so headless runs start Xvfb
(Debian package ``xvfb``) and use the ``xcb`` platform on it.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import time
from functools import partial
from pathlib import Path

from designer.lifetime import die_with_parent

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
        # a crash or a forgotten stop never leaves the X server running: it gets SIGTERM
        # when this process ends (SIGTERM, not SIGKILL, so that it removes its lock file)
        proc = subprocess.Popen([exe, f":{number}", "-screen", "0", screen, "-nolisten", "tcp"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                preexec_fn=partial(die_with_parent, os.getpid(),
                                                   signal.SIGTERM))
        for _ in range(100):
            if Path(f"/tmp/.X11-unix/X{number}").exists():
                if _lock_owner(number) == proc.pid:
                    return proc, f":{number}"
                # another server started on this number at the same moment and holds its
                # lock: ours gives up; try the next number
                break
            if proc.poll() is not None:
                break
            time.sleep(0.05)
        if proc.poll() is None:
            proc.terminate()
            proc.wait(5)
    raise XvfbError("could not start Xvfb on any display")


def _lock_owner(number: int) -> int | None:
    """The process id written in display ``number``'s lock file (the X server holding
    it), or None while there is none to read."""
    try:
        return int(Path(f"/tmp/.X{number}-lock").read_text().strip())
    except (OSError, ValueError):
        return None


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
