"""The figure products drawn by two forked processes (``designer compare``) are the ones
the figure thread draws; errors and lost processes reach the caller; nothing is left
running."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
from PIL import Image

from designer.evaluate import distance_statistics, grid_errors
from designer.evaluate.figures import FigureWriter

ROOT = Path(__file__).resolve().parents[2]

# a script run in a new, single-threaded process, as the program is when it forks
_SCRIPT = textwrap.dedent("""
    import json, os, signal, sys
    import numpy as np
    from designer.evaluate import distance_statistics, grid_errors
    from designer.evaluate.figure_processes import FigureProcesses

    out, mode = sys.argv[1], sys.argv[2]
    writers = FigureProcesses()
    report = {}
    rng = np.random.default_rng(3)
    xy = rng.uniform(0, 20, (4000, 2)) + [500000.0, 5000000.0]
    d = rng.normal(0, 0.05, 4000)
    stats = distance_statistics(d)
    grid = grid_errors(xy, d, cell_m=0.5)
    if mode == "kill":
        os.kill(writers._pid, signal.SIGKILL)
        os.waitid(os.P_PID, writers._pid, os.WEXITED | os.WNOWAIT)  # it has ended
    if mode == "abort":
        writers.abort()
    else:
        target = out if mode != "fail" else os.path.join(out, "missing", "folder")
        writers.submit("write_histogram_png", os.path.join(out, "histogram.png"), stats)
        writers.submit("write_error_map_png", os.path.join(target, "error_map.png"), grid,
                       limit_m=stats["abs_q95"])
        try:
            writers.close()
            report["closed"] = True
        except BaseException as exc:
            report["error"] = [type(exc).__name__, str(exc)]
    try:
        os.waitpid(-1, os.WNOHANG)
        report["children_left"] = True
    except ChildProcessError:
        report["children_left"] = False
    print(json.dumps(report))
""")


def _run(tmp_path: Path, mode: str) -> dict:
    env = dict(os.environ, MPLCONFIGDIR=str(tmp_path / "mpl"),
               PYTHONPATH=os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH"))
                                          if p))
    done = subprocess.run([sys.executable, "-c", _SCRIPT, str(tmp_path), mode], env=env,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def _pixels(path: Path) -> np.ndarray:
    return np.asarray(Image.open(path))


def test_processes_draw_the_pictures_the_thread_draws(tmp_path):
    report = _run(tmp_path, "draw")
    assert report == {"closed": True, "children_left": False}
    # the same figures from the figure thread in this process
    rng = np.random.default_rng(3)
    xy = rng.uniform(0, 20, (4000, 2)) + [500000.0, 5000000.0]
    d = rng.normal(0, 0.05, 4000)
    stats = distance_statistics(d)
    grid = grid_errors(xy, d, cell_m=0.5)
    (tmp_path / "thread").mkdir()
    with FigureWriter() as figures:
        figures.submit("write_histogram_png", tmp_path / "thread" / "histogram.png", stats)
        figures.submit("write_error_map_png", tmp_path / "thread" / "error_map.png", grid,
                       limit_m=stats["abs_q95"])
    for name in ("histogram.png", "error_map.png"):
        assert np.array_equal(_pixels(tmp_path / name), _pixels(tmp_path / "thread" / name))


def test_a_writer_error_reaches_the_caller_and_nothing_is_half_written(tmp_path):
    report = _run(tmp_path, "fail")
    assert report["error"][0] == "FileNotFoundError" and "missing" in report["error"][1]
    assert report["children_left"] is False
    assert (tmp_path / "histogram.png").is_file()  # the other process's file is whole
    assert not list(tmp_path.rglob("*.tmp*")) and not (tmp_path / "missing").exists()


def test_a_lost_process_is_an_error_not_a_silent_gap(tmp_path):
    report = _run(tmp_path, "kill")
    assert report["error"][0] == "RuntimeError" and "ended" in report["error"][1]
    assert report["children_left"] is False


def test_abort_stops_both_processes(tmp_path):
    report = _run(tmp_path, "abort")
    assert report == {"children_left": False}
    assert not list(tmp_path.glob("*.png"))
