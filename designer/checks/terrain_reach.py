"""What lies beyond the ground a terrain file holds: GCPs, buildings and flight-area
vertices inside the declared ``<extent>`` but outside the DEM's data or the terrain
mesh, where the scene has no ground under them (a GCP or building would float or be
clamped to an edge height, the flight would be planned over nothing).

The semantic checks (``designer.project.validate_*``) compare these places with the
declared extent; the file's own reach needs the file read, which is the scene's work,
so ``designer check`` asks here and prints the answers as warnings
(:class:`designer.checks.hard_cases.HardCaseWarning`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.checks.hard_cases import HardCaseWarning
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.validate_shared import plain_m


@dataclass(frozen=True)
class Reach:
    """The world X/Y box (m) a terrain file holds ground in, and how to name the file."""

    min_X: float
    min_Y: float
    max_X: float
    max_Y: float
    what: str  #: e.g. "the terrain mesh hill.ply"

    def contains(self, X: float, Y: float) -> bool:
        return self.min_X <= X <= self.max_X and self.min_Y <= Y <= self.max_Y

    def text(self) -> str:
        return (f"X {plain_m(self.min_X)}..{plain_m(self.max_X)}, "
                f"Y {plain_m(self.min_Y)}..{plain_m(self.max_Y)}")


def terrain_file_reach(project: m.Project, base_dir: Path) -> Reach | None:
    """The box a DEM holds data in (its nodes with heights) or a terrain mesh's vertices
    span, in world X/Y m; None for flat and procedural terrain (they fill the extent)."""
    from designer.scene.dem import dem_grid
    from designer.scene.mesh import load_mesh

    src = project.scene.terrain.source
    if isinstance(src, m.DemTerrain):
        x0, y0, dx, dy, heights = dem_grid(Path(base_dir) / src.file, project.crs)
        rows, cols = np.nonzero(np.isfinite(heights))
        if not len(rows):
            return None  # a DEM without data: refused where it is loaded
        return Reach(x0 + cols.min() * dx, y0 + rows.min() * dy, x0 + cols.max() * dx,
                     y0 + rows.max() * dy, f"the DEM {src.file}")
    if isinstance(src, m.MeshTerrain):
        xy = load_mesh(Path(base_dir) / src.file).vertices_world[:, :2]
        # mesh terrain files hold world − origin coordinates (designer.scene.build)
        E0, N0 = project.origin.E0, project.origin.N0
        return Reach(float(xy[:, 0].min()) + E0, float(xy[:, 1].min()) + N0,
                     float(xy[:, 0].max()) + E0, float(xy[:, 1].max()) + N0,
                     f"the terrain mesh {src.file}")
    return None


def _places(project: m.Project):
    """(element, name, X, Y) of every GCP, building corner or position and flight-area
    vertex, as the warnings name them."""
    for t in project.targets:
        yield "target", f"GCP {t.id}", t.true.X, t.true.Y
    for b in project.scene.buildings:
        if b.footprint:
            for i, p in enumerate(b.footprint):
                yield "footprint", f"building '{b.id}' corner {i + 1}", p.X, p.Y
        elif b.position is not None:
            yield "building", f"building '{b.id}'", b.position.X, b.position.Y
    plan = project.trajectory.flight_plan
    if plan is not None:
        for i, (x, y) in enumerate(plan.area):
            yield "area", f"flight area vertex {i + 1}", x, y


def terrain_reach_warnings(project: m.Project, base_dir: Path) -> list[HardCaseWarning]:
    """One warning per kind of place (GCPs, buildings, the flight area) lying outside the
    ground a DEM or terrain mesh holds, naming them (the first five) and the fix."""
    try:
        reach = terrain_file_reach(project, base_dir)
    except DesignerError:
        return []  # an unreadable file is refused by the file checks
    return reach_warnings(project, reach)


def reach_warnings(project: m.Project, reach: Reach | None) -> list[HardCaseWarning]:
    """:func:`terrain_reach_warnings` over a reach already read (None: no file, no
    warning); microseconds, so the window asks anew after every edit."""
    if reach is None:
        return []
    off: dict[str, list[str]] = {}
    for element, name, x, y in _places(project):
        if not reach.contains(x, y):
            off.setdefault(element, []).append(f"{name} (X {plain_m(x)}, Y {plain_m(y)})")
    fixes = {"target": "move the GCPs onto the terrain (GCPs panel)",
             "footprint": "move the buildings onto the terrain (Buildings panel)",
             "building": "move the buildings onto the terrain (Buildings panel)",
             "area": "draw the flight area over the terrain (Flight panel)"}
    out = []
    for element, names in off.items():
        shown = ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5
                                        else "")
        out.append(HardCaseWarning(
            element, f"{shown} {'lie' if len(names) > 1 else 'lies'} outside {reach.what}, "
                     f"which holds ground only over {reach.text()}: the scene has no "
                     "ground there",
            f"{fixes[element]}, or use a terrain file that covers "
            f"{'them' if len(names) > 1 else 'it'}"))
    return out
