"""Geometry checks shared by the survey tests (the scenes are in tests/synthetic.py)."""

import contextlib
import io
import re

import numpy as np

from designer.cli.main import main
from designer.core.heightfield import Heightfield


def refined(hf: Heightfield, factor: int) -> Heightfield:
    """The same bilinear surface on a grid ``factor`` times finer (a bilinear patch is
    bilinear on every sub-rectangle), so the core's half-cell marching steps finer."""
    ny, nx = hf.heights_m.shape
    x = hf.x0_m + np.arange((nx - 1) * factor + 1) * hf.dx_m / factor
    y = hf.y0_m + np.arange((ny - 1) * factor + 1) * hf.dy_m / factor
    X, Y = np.meshgrid(x, y)
    return Heightfield(hf.x0_m, hf.y0_m, hf.dx_m / factor, hf.dy_m / factor,
                       hf.height_at(X, Y))


def sight_clearance_deg(P, C, hf: Heightfield, tol_m: float, step_m: float = 0.005):
    """Smallest angle (deg) between each sight line P → C and the terrain below it,
    min over s ∈ [tol, |C − P|) of gap(s) / s, sampled every ``step_m``; < 0 = blocked."""
    out = []
    for p, c in zip(np.atleast_2d(P), np.atleast_2d(C), strict=True):
        d = c - p
        length = np.linalg.norm(d)
        s = np.arange(tol_m, length, step_m)
        q = p + s[:, None] * (d / length)
        gap = q[:, 2] - hf.height_at(q[:, 0], q[:, 1])
        out.append(np.degrees(np.nanmin(gap / s)))
    return np.array(out)


def survey_flown(tmp_path, altitude_m: float, front: float = 95.0, side: float = 20.0,
                 name: str = "low.xml"):
    """The survey template flown ``altitude_m`` above the mean terrain (which reaches
    9.4 m above its mean) at the given overlaps."""
    path = tmp_path / "s.xml"
    if not path.exists():
        with contextlib.redirect_stdout(io.StringIO()):
            assert main(["new", str(path), "--template", "survey"]) == 0
    text = path.read_text()
    text = re.sub(r"<altitude-agl-m>[^<]*<", f"<altitude-agl-m>{altitude_m}<", text)
    text = re.sub(r"<front-overlap-percent>[^<]*<", f"<front-overlap-percent>{front}<", text)
    text = re.sub(r"<side-overlap-percent>[^<]*<", f"<side-overlap-percent>{side}<", text)
    out = tmp_path / name
    out.write_text(text)
    return out
