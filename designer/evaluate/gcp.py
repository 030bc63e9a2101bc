"""Ground control and check point errors of a reconstruction.

World frame X east, Y north, Z up, metres. An error is ``estimated − true`` per axis;
dXY = hypot(dX, dY), dXYZ = |(dX, dY, dZ)|. Summaries are given separately for control
points (used to georeference, so their errors show the fit) and check points (held
back, so their errors show the accuracy), and for all points together:
RMSE_X = sqrt(mean(dX²)), RMSE_XY = sqrt(mean(dX² + dY²)), RMSE_XYZ likewise, plus the
mean per axis (the bias) and the largest dXYZ.

Estimates come from a CSV (``gcp_id, X, Y, Z``; see :func:`read_gcp_estimates_csv`) or
are triangulated from a COLMAP model and the GCP image observations
(:func:`designer.evaluate.triangulate.triangulate_gcps`).
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from designer.core.truth import GroundControlPoint
from designer.errors import DesignerError

_ID_NAMES = ("gcp_id", "id", "label", "name", "marker", "point", "#label")
_AXIS_NAMES = {"X": ("x", "e", "easting", "x_est", "est_x", "estimated_x", "x/east"),
               "Y": ("y", "n", "northing", "y_est", "est_y", "estimated_y", "y/north"),
               "Z": ("z", "h", "height", "altitude", "z_est", "est_z", "estimated_z",
                     "z/altitude")}


def gcp_errors(
    estimated: Mapping[str, Sequence[float]],
    truth: Sequence[GroundControlPoint],
    *,
    reference: str = "true",
) -> dict:
    """Per-point errors and per-role RMSE of ``estimated`` {gcp_id: (X, Y, Z)} against
    ``truth`` (its ``true_xyz``, or ``surveyed_xyz`` with ``reference="surveyed"``).

    Returns a JSON-ready dict: ``points`` (one row per GCP found in both, in truth
    order), ``summary`` {"control"|"check"|"all": {...}}, ``missing`` (truth ids
    without an estimate) and ``unknown`` (estimate ids not in the truth).
    """
    if reference not in ("true", "surveyed"):
        raise ValueError("reference must be 'true' or 'surveyed'")
    rows = []
    for g in truth:
        if g.gcp_id not in estimated:
            continue
        est = np.asarray(estimated[g.gcp_id], dtype=np.float64)
        if est.shape != (3,) or not np.isfinite(est).all():
            raise DesignerError(f"GCP {g.gcp_id}: estimate must be three finite numbers")
        ref = g.true_xyz if reference == "true" else g.surveyed_xyz
        dx, dy, dz = (est - ref).tolist()
        rows.append({"gcp_id": g.gcp_id, "role": g.role,
                     "X": float(est[0]), "Y": float(est[1]), "Z": float(est[2]),
                     "dX": dx, "dY": dy, "dZ": dz, "dXY": float(np.hypot(dx, dy)),
                     "dXYZ": float(np.sqrt(dx * dx + dy * dy + dz * dz))})
    if not rows:
        raise DesignerError("no GCP of the truth has an estimate: check that the ids match "
                            f"(truth: {', '.join(g.gcp_id for g in truth[:5])}...)")
    truth_ids = {g.gcp_id for g in truth}
    summary = {role: _summary([r for r in rows if r["role"] == role])
               for role in ("control", "check")}
    summary["all"] = _summary(rows)
    return {"reference": reference, "points": rows, "summary": summary,
            "missing": [g.gcp_id for g in truth if g.gcp_id not in estimated],
            "unknown": sorted(k for k in estimated if k not in truth_ids)}


def _summary(rows: list[dict]) -> dict:
    if not rows:
        return {"n": 0}
    d = np.array([[r["dX"], r["dY"], r["dZ"]] for r in rows])
    sq = d * d
    return {
        "n": len(rows),
        "rmse_X": float(np.sqrt(sq[:, 0].mean())), "rmse_Y": float(np.sqrt(sq[:, 1].mean())),
        "rmse_Z": float(np.sqrt(sq[:, 2].mean())),
        "rmse_XY": float(np.sqrt((sq[:, 0] + sq[:, 1]).mean())),
        "rmse_XYZ": float(np.sqrt(sq.sum(axis=1).mean())),
        "mean_X": float(d[:, 0].mean()), "mean_Y": float(d[:, 1].mean()),
        "mean_Z": float(d[:, 2].mean()),
        "max_XYZ": float(np.sqrt(sq.sum(axis=1)).max()),
    }


def read_gcp_estimates_csv(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """{gcp_id: (X, Y, Z)} from a CSV with a header naming an id column (gcp_id, id,
    label, name or marker) and X, Y, Z columns (x/y/z, e/n/h, easting/northing/height).

    '#' comment lines before the header are skipped; the delimiter may be a comma,
    semicolon or tab. Designer's own gcp_truth.csv reads too (its true_X/Y/Z columns).
    """
    path = Path(path)
    if not path.is_file():
        raise DesignerError(f"GCP estimates {path} do not exist")
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines()
             if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise DesignerError(f"GCP estimates {path} have no rows")
    delimiter = next((d for d in (",", ";", "\t") if d in lines[0]), ",")
    reader = csv.reader(io.StringIO("\n".join(lines)), delimiter=delimiter)
    header = [h.strip().lower() for h in next(reader)]
    id_col = next((header.index(n) for n in _ID_NAMES if n in header), None)
    cols = []
    for axis, names in _AXIS_NAMES.items():
        names = (*names, f"true_{axis.lower()}")
        cols.append(next((header.index(n) for n in names if n in header), None))
    if id_col is None or None in cols:
        raise DesignerError(f"GCP estimates {path}: need an id column and X, Y, Z columns in "
                            f"the header, found {header}")
    out: dict[str, np.ndarray] = {}
    for line_no, row in enumerate(reader, start=2):
        try:
            out[row[id_col].strip()] = np.array([float(row[c]) for c in cols])
        except (ValueError, IndexError):
            raise DesignerError(f"GCP estimates {path}: row {line_no} {row} is not an id and "
                                "three numbers") from None
    return out


def format_gcp_table(result: dict) -> list[str]:
    """Markdown lines: the per-role RMSE table, then the per-point table (metres)."""
    lines = ["| points | n | RMSE X | RMSE Y | RMSE Z | RMSE XY | RMSE XYZ | mean Z | max XYZ |",
             "|---|---|---|---|---|---|---|---|---|"]
    for role in ("control", "check", "all"):
        s = result["summary"][role]
        if not s["n"]:
            lines.append(f"| {role} | 0 | | | | | | | |")
            continue
        lines.append(f"| {role} | {s['n']} | " + " | ".join(
            f"{s[k]:.4f}" for k in ("rmse_X", "rmse_Y", "rmse_Z", "rmse_XY", "rmse_XYZ",
                                    "mean_Z", "max_XYZ")) + " |")
    lines += ["", "| GCP | role | dX | dY | dZ | dXY | dXYZ |", "|---|---|---|---|---|---|---|"]
    for r in result["points"]:
        lines.append(f"| {r['gcp_id']} | {r['role']} | " + " | ".join(
            f"{r[k]:+.4f}" if k[1] in "XYZ" and len(k) == 2 else f"{r[k]:.4f}"
            for k in ("dX", "dY", "dZ", "dXY", "dXYZ")) + " |")
    if result["missing"]:
        lines += ["", f"Not estimated (not reconstructed): {', '.join(result['missing'])}"]
    return lines
