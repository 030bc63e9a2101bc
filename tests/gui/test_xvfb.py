"""The virtual X display dies with the process that started it, cleanly: killed
outright (SIGKILL, no clean-up of its own), the starter takes its Xvfb with it, and the
X server, stopped by SIGTERM rather than SIGKILL, removes its lock file (a display number
left locked would be skipped by every later start)."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.skipif(shutil.which("Xvfb") is None, reason="Xvfb not installed")


def _alive(pid: int) -> bool:
    """True while ``pid`` runs (a zombie waiting to be reaped counts as ended)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, IndexError):
        return False
    return state not in ("Z", "X")


def test_a_killed_starter_takes_its_xvfb_with_it_and_the_lock_file_goes():
    code = ("import sys, time\n"
            "from designer.gui.xvfb import start_xvfb\n"
            "proc, display = start_xvfb(first=140)\n"
            "print(proc.pid, display, flush=True)\n"
            "time.sleep(60)\n")
    with subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True,
                          cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)}) as starter:
        try:
            pid_text, display = starter.stdout.readline().split()
            xvfb_pid, number = int(pid_text), display.lstrip(":")
            lock = Path(f"/tmp/.X{number}-lock")
            assert _alive(xvfb_pid) and lock.exists()
            starter.send_signal(signal.SIGKILL)
            starter.wait(10)
            deadline = time.monotonic() + 10
            while (_alive(xvfb_pid) or lock.exists()) and time.monotonic() < deadline:
                time.sleep(0.05)
            assert not _alive(xvfb_pid), "Xvfb outlived the process that started it"
            assert not lock.exists(), "Xvfb was killed without removing its lock file"
        finally:
            if starter.poll() is None:
                starter.kill()


def test_starts_at_the_same_moment_get_a_display_each(tmp_path):
    """Two test workers starting their displays at once: each gets its own server (a start
    that lost the race for a number must not take the other's display, which would go
    when the other worker stops it)."""
    go = tmp_path / "go"
    code = ("import sys, time\n"
            "from pathlib import Path\n"
            "from designer.gui.xvfb import start_xvfb\n"
            "print('ready', flush=True)\n"
            f"while not Path({str(go)!r}).exists():\n"
            "    time.sleep(0.001)\n"
            "proc, display = start_xvfb(first=160)\n"
            "print(proc.pid, display, flush=True)\n"
            "sys.stdin.read()\n")  # until the test closes its stdin
    for round_ in range(2):  # each round races (Xvfb settles a tie on one number in ~5 s)
        go.unlink(missing_ok=True)
        starters = [subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, text=True, cwd=ROOT,
                                     env={**os.environ, "PYTHONPATH": str(ROOT)})
                    for _ in range(2)]
        try:
            # both waiting for the word
            assert [s.stdout.readline().strip() for s in starters] == ["ready", "ready"]
            go.touch()
            got = [tuple(s.stdout.readline().split()) for s in starters]
            (_, display_a), (_, display_b) = got
            assert display_a != display_b, f"round {round_}: both on {display_a}"
            for pid, display in got:
                assert _alive(int(pid)), f"the server of {display} is gone"
                lock = Path(f"/tmp/.X{display.lstrip(':')}-lock").read_text()
                assert int(lock.strip()) == int(pid)
        finally:
            for s in starters:
                s.stdin.close()
                s.wait(10)
                s.stdout.close()
