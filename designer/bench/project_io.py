"""Read + validate a large project: 10,000 explicit camera poses and 1,000 GCPs.

Run: ``designer bench project-io``. It prints a
table; ``run()`` and ``format_table()`` follow the ``designer bench`` interface so the
command can list it. Target: read + validate (XSD and semantic checks) in < 1 s.
"""

from __future__ import annotations

import dataclasses
import sys
import tempfile
from pathlib import Path

if __package__ in (None, ""):  # run as a script from the repository root
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from designer.bench.table import Column, text_table
from designer.bench.timing import best_of
from designer.project import load_project, template, write_project
from designer.project import model as m
from designer.project.validate import semantic_problems
from designer.project.xml_read import read_project_file


def large_project(n_photos: int = 10_000, n_gcps: int = 1_000, seed: int = 1) -> m.Project:
    """The example survey with ``n_photos`` explicit poses and ``n_gcps`` surveyed GCPs."""
    base = template("survey").project
    rng = np.random.default_rng(seed)
    e = base.scene.terrain.extent
    xy = rng.uniform([e.min_X, e.min_Y], [e.max_X, e.max_Y], size=(n_photos + n_gcps, 2))
    angles = rng.normal(0.0, 2.0, size=(n_photos, 3))
    photos = tuple(
        m.ExteriorOrientation(f"IMG_{i:05d}.png", "p4p", float(x), float(y), 50.0 + i % 7,
                              float(a[0]), float(a[1]), float(a[2]))
        for i, ((x, y), a) in enumerate(zip(xy[:n_photos], angles, strict=True)))
    sigma = m.Sigma3(0.01, 0.01, 0.02)
    targets = tuple(
        m.Target(f"G{i:04d}", "control" if i % 3 else "check", "checker", 0.5,
                 m.TruePosition(float(x), float(y), 1.0),
                 m.SurveyedPosition(m.Point3(float(x) + 0.003, float(y) - 0.002, 1.01), sigma))
        for i, (x, y) in enumerate(xy[n_photos:]))
    scene = dataclasses.replace(base.scene, targets=m.Targets(targets))
    return dataclasses.replace(base, scene=scene, trajectory=m.Trajectory(photos, None))


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    """Seconds for each stage; ``scale`` shrinks the project (tests use a small one)."""
    n_photos, n_gcps = max(1, int(10_000 * scale)), max(1, int(1_000 * scale))
    project = large_project(n_photos, n_gcps)
    label = f"{n_photos} poses + {n_gcps} GCPs"
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "large.xml"
        write_s, _ = best_of(repeats, lambda: write_project(project, path))
        size_mb = path.stat().st_size / 1e6
        parsed, smap = read_project_file(path)
        assert parsed == project
        rows = [
            ("write (model -> XML, atomic)", write_s),
            ("read + XSD (lxml) -> model", best_of(repeats, lambda: read_project_file(path))[0]),
            ("semantic checks", best_of(repeats,
                                        lambda: semantic_problems(parsed, path.parent, smap))[0]),
            ("read + validate (load_project)", best_of(repeats, lambda: load_project(path))[0]),
        ]
    return [{"case": label, "stage": stage, "seconds": s, "size_mb": size_mb}
            for stage, s in rows]


def format_table(rows: list[dict]) -> str:
    return text_table(
        [Column("case", "<26", "case"), Column("stage", "<32", "stage"),
         Column("seconds", ">8.3f", "seconds"), Column("file MB", ">8.2f", "size_mb")], rows,
        "(best of the repeats; target: read + validate < 1 s)")


def main() -> int:
    print(format_table(run()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
