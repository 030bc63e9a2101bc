"""Camera stations under the ground: below the terrain, inside a building or a plant, or
closer to its surface than the camera's near distance (issue #53).

Such a station's images are rendered from inside the scene (the renderer's camera clips
everything nearer than :data:`NEAR_M`), and every figure measured from it — GSD, overlaps,
footprints — is meaningless, so ``designer check`` and ``designer plan`` refuse it and the
window lists it among its problems. The clearance is vertical: the station's height above
the highest surface straight below or above it (the terrain's height field, a building's
triangles, a plant's crown taken as a cylinder of its crown's diameter and its height). A
station off the terrain's height field has nothing known below it and is not judged; a
terrain mesh is not judged (as the plan's analysis, it needs a height field).

Cheap enough to run after every edit: a bilinear height per station, a box test per
building triangle and a k-d tree query per station (a few ms at 5,000 stations).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError
from designer.project import model as m
from designer.project.problems import Issue

#: the camera's near distance (m): the render camera clips everything nearer than this
#: (``designer.render.job_spec.CameraSpec.clip_start_m``; a test holds the two equal)
NEAR_M = 0.01
#: what a station can be under, in the order they are named
SURFACES = ("terrain", "buildings", "vegetation")


def station_clearance(C_world: np.ndarray, hf, buildings=(), plants=None
                      ) -> tuple[np.ndarray, np.ndarray]:
    """How high each station ``C_world`` (N, 3), world m, is above the highest surface
    at its X/Y: (N,) metres (negative: below it; NaN: off the height field ``hf``, or
    ``hf`` None) and (N,) what that surface is (one of :data:`SURFACES`, "" where NaN).

    ``buildings``: [(vertices_world (V, 3), faces (F, 3))] closed meshes; ``plants``:
    (base_world (P, 3), height_m (P,), crown_m (P,)) or None."""
    C = np.asarray(C_world, dtype=float).reshape(-1, 3)
    top = np.full(len(C), np.nan)
    what = np.full(len(C), "", dtype=object)
    if hf is None or not len(C):
        return top, what
    top = np.asarray(hf.height_at(C[:, 0], C[:, 1]), dtype=float).reshape(-1)
    what[np.isfinite(top)] = "terrain"
    for vertices, faces in buildings:
        _raise(top, what, _triangles_top_m(C[:, :2], vertices, faces), "buildings")
    if plants is not None:
        _raise(top, what, _plants_top_m(C[:, :2], *plants), "vegetation")
    what[~np.isfinite(top)] = ""
    return C[:, 2] - top, what


def _raise(top: np.ndarray, what: np.ndarray, other: np.ndarray, name: str) -> None:
    """``top`` raised in place to ``other`` where that is higher (on the height field)."""
    higher = np.isfinite(top) & np.isfinite(other) & (other > top)
    top[higher] = other[higher]
    what[higher] = name


def _triangles_top_m(xy: np.ndarray, vertices, faces) -> np.ndarray:
    """(N,) the highest Z of the triangles over each point (N, 2); NaN over none.
    Walls (no area seen from above) are skipped: their tops are edges of roofs."""
    top = np.full(len(xy), np.nan)
    tri = np.asarray(vertices, dtype=float)[np.asarray(faces, dtype=np.int64)]
    if not len(tri):
        return top
    lo, hi = tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1)
    for start in range(0, len(xy), 512):  # at most 512 × F booleans at a time
        p = xy[start:start + 512]
        box = ((p[:, None, 0] >= lo[None, :, 0]) & (p[:, None, 0] <= hi[None, :, 0])
               & (p[:, None, 1] >= lo[None, :, 1]) & (p[:, None, 1] <= hi[None, :, 1]))
        i, k = np.nonzero(box)
        if not len(i):
            continue
        a, b, c = tri[k, 0], tri[k, 1], tri[k, 2]
        q = p[i]
        det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
        flat = np.abs(det) > 1e-12
        with np.errstate(divide="ignore", invalid="ignore"):
            u = ((q[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                 - (c[:, 0] - a[:, 0]) * (q[:, 1] - a[:, 1])) / det
            v = ((b[:, 0] - a[:, 0]) * (q[:, 1] - a[:, 1])
                 - (q[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])) / det
            z = a[:, 2] + u * (b[:, 2] - a[:, 2]) + v * (c[:, 2] - a[:, 2])
        eps = 1e-9
        inside = flat & (u >= -eps) & (v >= -eps) & (u + v <= 1 + eps)
        part = np.full(len(p), -np.inf)
        np.maximum.at(part, i[inside], z[inside])
        part[~np.isfinite(part)] = np.nan
        top[start:start + 512] = part
    return top


#: the plants nearest each station weighed (a k-d tree query, vectorised): with one crown
#: size the nearest is the one over it if any is; in a thicket of mixed sizes a taller
#: plant further off may be missed, but a station among the plants is found all the same
NEAREST_PLANTS = 16


def _plants_top_m(xy: np.ndarray, base_world, height_m, crown_m) -> np.ndarray:
    """(N,) the highest plant top over each point (N, 2), a plant taken as an upright
    cylinder of its crown's diameter (of the :data:`NEAREST_PLANTS` nearest); NaN over
    none."""
    base = np.asarray(base_world, dtype=float).reshape(-1, 3)
    top = np.full(len(xy), np.nan)
    if not len(base):
        return top
    from scipy.spatial import cKDTree

    radius = 0.5 * np.asarray(crown_m, dtype=float)
    tips = base[:, 2] + np.asarray(height_m, dtype=float)
    k = min(len(base), NEAREST_PLANTS)
    d, idx = cKDTree(base[:, :2]).query(xy, k=k, distance_upper_bound=float(radius.max()))
    d, idx = d.reshape(len(xy), k), idx.reshape(len(xy), k)
    found = idx < len(base)
    safe = np.where(found, idx, 0)
    under = found & (d <= radius[safe])
    top[:] = np.where(under, tips[safe], -np.inf).max(axis=1)
    top[~under.any(axis=1)] = np.nan
    return top


@dataclass(frozen=True)
class LowStations:
    """Stations below, or within :data:`NEAR_M` of, what the images look at: how many of
    how many, the lowest one's image name and clearance (m, negative: below), what it is
    under and what all of them are under (:data:`SURFACES`), and how the flight is set
    (``flight``: "altitude" or "gsd" for a flight plan flown by either, None without
    one; ``terrain_following``: the plan's setting)."""

    n_low: int
    n_stations: int
    lowest_name: str
    lowest_m: float
    under: str
    kinds: tuple[str, ...]
    flight: str | None = None
    terrain_following: bool = False

    @property
    def raise_m(self) -> float:
        """How far (m, rounded up to 0.1 m) the lowest station must rise to clear it."""
        return math.ceil(10 * (NEAR_M - self.lowest_m)) / 10

    def sentence(self) -> str:
        """What is wrong, with how many and the lowest clearance (no element names)."""
        near = f"{100 * NEAR_M:g} cm"
        where = {
            ("terrain",): f"below the terrain or within {near} of it",
            ("buildings",): f"inside buildings or within {near} of their roofs",
            ("vegetation",): f"inside plants or within {near} of their tops",
        }.get(self.kinds)
        if where is None:
            inside = [w for k, w in (("buildings", "buildings"), ("vegetation", "plants"))
                      if k in self.kinds]
            parts = (["below the terrain"] if "terrain" in self.kinds else []) + (
                ["inside " + " or ".join(inside)] if inside else [])
            where = f"{' or '.join(parts)}, or within {near} of them"
        what = ("it" if len(self.kinds) == 1 else
                {"terrain": "the terrain", "buildings": "a building's roof",
                 "vegetation": "a plant's top"}[self.under])
        depth = abs(self.lowest_m)
        amount = f"{depth:.2f} m" if depth >= 0.01 else f"{100 * depth:.1f} cm"
        side = "below" if self.lowest_m < 0 else "above"
        return (f"{self.n_low} of {self.n_stations} camera stations are {where}; the "
                f"lowest, {self.lowest_name}, is {amount} {side} {what}: their images would "
                "be taken from inside the scene")

    def fix(self) -> str:
        """The fix in the project file's words."""
        by = f"by more than {self.raise_m:g} m"
        if self.flight == "altitude":
            out = f"raise the flight height (altitude-agl-m) {by}"
        elif self.flight == "gsd":
            out = f"raise the GSD (gsd-m) until the flight height rises {by}"
        else:
            return f"raise the photos, orbits and facade flights {by}"
        if self.kinds == ("terrain",) and not self.terrain_following:
            out += ", or fly with terrain-following"
        return out

    def panel_fix(self) -> str:
        """The fix in the window's words (the Flight panel's fields)."""
        by = f"by more than {self.raise_m:g} m"
        if self.flight == "altitude":
            out = f"raise the height above ground in the Flight panel {by}"
        elif self.flight == "gsd":
            out = ("raise the ground sample distance in the Flight panel until the flight "
                   f"height rises {by}")
        else:
            return f"raise the photos, orbits and facade flights {by}"
        if self.kinds == ("terrain",) and not self.terrain_following:
            out += ", or tick terrain following"
        return out


def low_stations(names, clearance_m: np.ndarray, what: np.ndarray,
                 plan: m.FlightPlan | None) -> LowStations | None:
    """The stations (``names``) whose clearance (:func:`station_clearance`) is below
    :data:`NEAR_M`, summed up; None when there are none."""
    clearance_m = np.asarray(clearance_m, dtype=float)
    with np.errstate(invalid="ignore"):
        low = np.flatnonzero(np.isfinite(clearance_m) & (clearance_m < NEAR_M))
    if not len(low):
        return None
    k = int(low[np.argmin(clearance_m[low])])
    kinds = tuple(s for s in SURFACES if s in set(what[low]))
    flight = None if plan is None else ("altitude" if plan.altitude_agl_m is not None
                                        else "gsd")
    return LowStations(len(low), len(clearance_m), str(names[k]), float(clearance_m[k]),
                       str(what[k]), kinds, flight,
                       bool(plan is not None and plan.terrain_following))


def low_stations_issue(project: m.Project, low: LowStations | None) -> list[Issue]:
    """``low`` as the issue of the flight plan (or the trajectory without one), code
    ``stations-too-low`` with ``low`` as its value; [] for None."""
    if low is None:
        return []
    plan = project.trajectory.flight_plan
    obj, tag = (plan, "flight-plan") if plan is not None else (project.trajectory,
                                                              "trajectory")
    return [Issue(obj, tag, f"{low.sentence()}; {low.fix()}", code="stations-too-low",
                  value=low)]


def clearance_issues(project: m.Project, base_dir: Path, hf=None, images=None
                     ) -> list[Issue]:
    """The stations of ``project`` (files relative to ``base_dir``) below the terrain,
    buildings or plants, as :func:`low_stations_issue`; ``hf`` and ``images``
    (project_images) when the caller holds them already. [] when the terrain, the
    stations, or a terrain mesh cannot be judged (check says why elsewhere)."""
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_images

    try:
        if hf is None:
            hf = build_heightfield(project.scene.terrain, Path(base_dir), project.crs)
        if hf is None:
            return []
        if images is None:
            images = project_images(project, hf)
    except DesignerError:
        return []
    platform = images.platform
    C = np.array([s.C_world for s in platform], dtype=float).reshape(-1, 3)
    clearance, what = station_clearance(C, hf, *_standing(project, Path(base_dir), hf))
    low = low_stations([s.image_name for s in platform], clearance, what,
                       project.trajectory.flight_plan)
    return low_stations_issue(project, low)


def refuse_low_stations(project: m.Project, smap, path: Path) -> None:
    """Raise a ProjectError (``FILE:LINE:COL: <flight-plan>: …``) when stations of
    ``project``, read from ``path`` with its SourceMap ``smap``, are under the ground:
    ``designer plan`` and ``designer render`` refuse such a file (the window saves it as
    work in progress)."""
    from designer.project.problems import ProjectError

    issues = clearance_issues(project, path.parent)
    if issues:
        raise ProjectError(str(path), [smap.locate(i) for i in issues])


def _standing(project: m.Project, base_dir: Path, hf) -> tuple[list, tuple | None]:
    """The buildings' meshes and the plants (base, height, crown) standing on ``hf``,
    as the renderer places them; what cannot be built is left out (its file check says
    why)."""
    from designer.scene.surfaces import Ground

    ground = Ground(hf, None)
    buildings, plants = [], None
    if project.scene.buildings:
        from designer.scene.buildings import building_meshes_world

        try:
            buildings = building_meshes_world(project, base_dir, ground)
        except (DesignerError, OSError):
            buildings = []
    if project.scene.vegetation is not None:
        from designer.scene.vegetation import place_vegetation

        try:
            plants = plant_cylinders(place_vegetation(project, base_dir, ground))
        except (DesignerError, OSError):
            plants = None
    return buildings, plants


def plant_cylinders(sets) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(base_world (P, 3), height_m (P,), crown_m (P,)) of the plants of ``sets``
    (designer.scene.vegetation.PlantSet)."""
    sets = list(sets)
    if not sets:
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0)
    return (np.vstack([s.base_world for s in sets]).reshape(-1, 3),
            np.concatenate([s.height_m for s in sets]),
            np.concatenate([s.crown_m for s in sets]))
