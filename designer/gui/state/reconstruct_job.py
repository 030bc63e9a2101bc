"""Reconstructing a rendered survey from the window, as plain data (Qt-free).

The Results panel runs two commands, one after the other, each in its own process:

1. ``designer reconstruct SURVEY -o SURVEY/reconstruction-MODE --mode MODE`` — COLMAP
   (pycolmap): SIFT features, matching, triangulation with the true poses or free SfM
   georeferenced by the control GCPs; writes ``cloud.ply`` and ``gcp_residuals.csv``;
2. ``designer compare CLOUD PROJECT.xml -o …/compare --truth SURVEY`` — exact signed
   distances of the cloud to the true terrain and GCP plates, statistics, error maps,
   GCP and camera errors; writes ``distances.ply`` and a report.

:func:`stage_of_line` turns the commands' log lines into the stage shown by the
progress bar; :func:`read_compared_cloud` reads what ``designer compare`` wrote.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError

#: what ``designer reconstruct --mode`` offers, as shown in the panel
MODES = (("true poses (ideal: triangulation only)", "known-poses"),
         ("free SfM, georeferenced by the control GCPs", "free"))

#: the stages of a run, in order; a log line starting a stage contains its marker
STAGES = (
    ("SIFT features", ("features:",)),
    ("matching image pairs", ("matching:",)),
    ("triangulation / SfM", ("triangulating", "incremental SfM")),
    ("georeferencing", ("georeferenced", "images registered")),
    ("signed distances to the true surface", ()),  # the compare command
)
COMPARE_STAGE = len(STAGES) - 1


def mode_of(out_dir: Path) -> str | None:
    """The ``--mode`` a reconstruction folder (``reconstruction-MODE``, see
    :attr:`ReconstructJob.out_dir`) was made with, or None for another folder."""
    name = Path(out_dir).name
    return next((mode for _text, mode in MODES if name == f"reconstruction-{mode}"), None)


def stage_of_line(line: str) -> int | None:
    """The stage a log line of ``designer reconstruct`` announces, or None."""
    for index, (_title, markers) in enumerate(STAGES):
        if any(marker in line for marker in markers):
            return index
    return None


@dataclass(frozen=True)
class ReconstructJob:
    """Where a reconstruction of ``survey_dir`` goes and the commands that make it."""

    project_path: Path
    survey_dir: Path
    mode: str = "known-poses"
    #: SIFT features per image overriding the project's <processing> (None: its value)
    max_features: int | None = None

    @property
    def out_dir(self) -> Path:
        return self.survey_dir / f"reconstruction-{self.mode}"

    @property
    def compare_dir(self) -> Path:
        return self.out_dir / "compare"

    @property
    def distances_ply(self) -> Path:
        return self.compare_dir / "distances.ply"

    @property
    def gcp_residuals_csv(self) -> Path:
        return self.out_dir / "gcp_residuals.csv"

    def commands(self) -> list[list[str]]:
        """argv of ``designer reconstruct`` (with the project's ``<processing>``: calibration,
        GCPs, position priors, matching, dense) and then ``designer compare``."""
        designer = [sys.executable, "-m", "designer"]
        features = [] if self.max_features is None else ["--max-features",
                                                         str(self.max_features)]
        return [
            [*designer, "reconstruct", str(self.survey_dir), "-o", str(self.out_dir),
             "--mode", self.mode, "--project", str(self.project_path), *features],
            [*designer, "compare", str(self.out_dir / "cloud.ply"), str(self.project_path),
             "-o", str(self.compare_dir), "--truth", str(self.survey_dir)],
        ]


@dataclass(frozen=True)
class DenseProducts:
    """What the dense stage of a reconstruction wrote (``summary.json`` ``dense``)."""

    folder: Path
    points: int
    matcher: str
    #: amplitude of the dome (or bowl) fitted to the DEM of difference, m (None: none)
    dome_amplitude_m: float | None

    @property
    def cloud_ply(self) -> Path:
        return self.folder / "dense.ply"

    @property
    def dod_png(self) -> Path:
        return self.folder / "dod.png"

    def text(self) -> str:
        dome = ("no dome" if self.dome_amplitude_m is None
                else f"dome amplitude {1000 * self.dome_amplitude_m:+.1f} mm")
        return f"dense cloud: {self.points:,} points ({self.matcher}); DEM of difference: {dome}"


def dense_products(out_dir: Path) -> DenseProducts | None:
    """The dense products of the reconstruction in ``out_dir`` (None when its
    ``summary.json`` has no finished dense stage)."""
    import json

    try:
        summary = json.loads((Path(out_dir) / "summary.json").read_text())
    except (OSError, ValueError):
        return None
    dense = summary.get("dense") or {}
    if dense.get("status") != "ok" or not (Path(out_dir) / "dense.ply").is_file():
        return None
    return DenseProducts(Path(out_dir), int(dense.get("points", 0)),
                         str(dense.get("matcher", "")), dense.get("dome_amplitude_m"))


def processing_text(p) -> str:
    """One line of the project's ``<processing>`` for the Results panel."""
    if p is None:
        return "designer reconstruct's defaults (Processing panel)"
    parts = [f"calibration {p.calibration.mode}", f"GCPs {p.gcps.mode}",
             f"{p.matching.max_features} features"]
    if p.position_prior.mode != "none":
        parts.append(f"{p.position_prior.mode} positions")
    parts.append("dense cloud" if p.dense != "none" else "sparse only")
    return ", ".join(parts) + " (Processing panel)"


def survey_status(survey_dir: Path) -> tuple[int, str]:
    """(number of rendered images, a line describing the folder) of a render output;
    0 images when the folder cannot be reconstructed yet."""
    from designer.sfm.inputs import check_survey_folder

    try:
        _gt, _images, names = check_survey_folder(Path(survey_dir))
    except DesignerError as error:
        return 0, str(error)
    return len(names), f"{survey_dir}: {len(names)} rendered images with their ground truth"


def read_compared_cloud(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Points (N, 3, world, m) and signed distances (N, m) from ``designer compare``'s
    ``distances.ply`` (NaN distances — beyond a maximum distance — are left out)."""
    from plyfile import PlyData

    from designer.evaluate.writers import SCALAR_NAME

    vertex = PlyData.read(str(path))["vertex"]
    names = vertex.data.dtype.names
    if SCALAR_NAME not in names:
        raise DesignerError(f"{path}: no {SCALAR_NAME} property; is it designer compare's "
                            "distances.ply?")
    xyz = np.column_stack([np.asarray(vertex[c], dtype=float) for c in ("x", "y", "z")])
    d = np.asarray(vertex[SCALAR_NAME], dtype=float)
    keep = np.isfinite(d)
    return xyz[keep], d[keep]
