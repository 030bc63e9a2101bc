"""`designer bench effects` on a small camera: every row measured, the chains complete."""

import subprocess
import sys

from designer.bench import effects


def test_rows_and_table_on_a_small_camera():
    rows = effects.run(repeats=1, scale=0.01)
    cases = [r["case"] for r in rows]
    assert cases[:4] == ["warp build (once per camera)", "first frame (compiles/loads kernels)",
                         "example survey chain", "every effect"]
    assert all(r["seconds"] > 0 for r in rows)
    every = rows[3]
    assert every["note"].split(" → ") == ["motion_blur", "distortion", "vignetting", "defocus",
                                          "blur", "sensor", "noise_dn", "jpeg"]
    assert every["bytes"] > 1000  # a JPEG file was produced
    table = effects.format_table(rows)
    assert "example survey chain" in table and "numba threads" in table


def test_the_cli_knows_the_benchmark():
    out = subprocess.run([sys.executable, "-m", "designer", "bench", "--help"],
                         capture_output=True, text=True, check=True).stdout
    assert "effects" in out
