"""What a flight delivers over the real terrain, for the Flight and GCP panels (Qt-free).

The same analysis as ``designer plan`` (:func:`designer.survey.coverage.analyse_plan`):
GSD over the terrain, achieved front and side overlaps, images whose principal ray
meets the terrain inside the area, images per GCP; plus how much of each image shows
the terrain at all. It runs in a worker thread (a few seconds for large flights).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from designer.gui.state.wording import count
from designer.project import model as m

#: achieved overlaps (5 % quantile over the stations) below these are warned about
LOW_FRONT_OVERLAP = 0.6
LOW_SIDE_OVERLAP = 0.3
#: a GCP needs at least this many images to be measured reliably
MIN_GCP_IMAGES = 3


@dataclass(frozen=True, eq=False)
class PlanFigures:
    """Figures over the real terrain (m, fractions 0–1) and the warnings they raise."""

    n_images: int                      # stations (with a rig: its planning camera's images)
    gsd_min_m: float
    gsd_max_m: float
    gsd_median_m: float
    front_overlap_median: float
    front_overlap_p05: float
    side_overlap_median: float
    side_overlap_p05: float
    images_over_area: int
    images_over_terrain: int
    #: (M,) share of each rendered image (every camera of a rig) that shows the terrain
    terrain_share: np.ndarray
    image_names: tuple[str, ...]       # (M,) the rendered images' names
    gcp_ids: tuple[str, ...]
    gcp_images: np.ndarray             # (G,) rendered images seeing each GCP
    area_seen: dict[int, float]
    warnings: tuple[str, ...]
    n_rendered: int = 0                # every image rendered (all cameras of a rig)
    #: per GCP: the rendered images that see it (indices into image_names, every camera
    #: of a rig) and where (px of that image, projected with its own pose and camera)
    gcp_image_index: tuple[np.ndarray, ...] = ()
    gcp_uv_px: tuple[np.ndarray, ...] = ()
    #: the finest GSD (m/px) of any rendered image, sampled as ``designer check`` does
    #: (designer.checks.hard_cases.finest_gsd_m): the texture's texel is weighed
    #: against it as it is edited
    finest_gsd_m: float = float("nan")

    def observations(self, image: int) -> list[tuple[str, float, float]]:
        """(GCP id, u, v) of the GCPs rendered image ``image`` (an index into
        ``image_names``) sees (its pixels; u right, v down, from the top-left corner of
        the top-left pixel)."""
        out = []
        for gid, images, uv in zip(self.gcp_ids, self.gcp_image_index, self.gcp_uv_px,
                                   strict=True):
            for k in np.flatnonzero(np.asarray(images) == image):
                out.append((gid, float(uv[k][0]), float(uv[k][1])))
        return out


def _pct(v: float) -> str:
    return "–" if not np.isfinite(v) else f"{100 * v:.0f} %"


def compute_plan_figures(project: m.Project, terrain, stations_result, targets_result
                         ) -> PlanFigures:
    """Analyse the stations over the terrain (a height field); see the module doc."""
    from designer.errors import DesignerError
    from designer.gui.state.job_control import check
    from designer.survey.coverage import analyse_plan

    hf = terrain.heightfield if terrain is not None else None
    if hf is None or terrain.raycaster is None:
        raise DesignerError("the analysis over the terrain needs a height-field terrain")
    stations = stations_result.stations
    interior = stations_result.interior
    scale = project.render.resolution_scale
    if scale != 1.0:
        from designer.project.interiors import render_interior

        interior = render_interior(project.camera(stations_result.camera_id), scale)
    plan = project.trajectory.flight_plan
    e = project.scene.terrain.extent
    area = (np.array(plan.area) if plan is not None and len(plan.area) >= 3 else
            np.array([[e.min_X, e.min_Y], [e.max_X, e.min_Y], [e.max_X, e.max_Y],
                      [e.min_X, e.max_Y]]))
    gcp_xyz = (targets_result.true_xyz if targets_result is not None
               and len(targets_result.ids) else None)
    from designer.survey.project_poses import project_images
    from designer.survey.surroundings import image_ground

    images = (stations_result.images if stations_result.images is not None
              else project_images(project, hf))
    # over the rendered terrain (the declared one and its surroundings), as designer plan:
    # past the declared terrain's edge the images see the surroundings, or void
    # a newer edit stops this analysis between its stages (job_control)
    check()
    ground = image_ground(project, hf, images, stations_result.grown, check=check)
    check()
    analysis = analyse_plan(stations, interior, ground.rendered, area,
                            raycaster=ground.raycaster)
    check()
    s = analysis.summary()
    centre = analysis.stations.centre_ground_xyz
    gsd = analysis.coverage.gsd_mean_m
    gsd = gsd[np.isfinite(gsd)]
    from designer.checks.hard_cases import finest_gsd_m, network_warnings

    seen = _rendered_images(project, images, ground, terrain.raycaster, gcp_xyz)
    check()
    share, names = seen.terrain_share, seen.names
    ids = tuple(targets_result.ids) if gcp_xyz is not None else ()
    gcp_images = np.array([len(k) for k in seen.gcp_image_index], dtype=int)
    figures = dict(
        n_images=len(stations), n_rendered=len(names),
        gsd_min_m=float(gsd.min()) if gsd.size else float("nan"),
        gsd_max_m=float(gsd.max()) if gsd.size else float("nan"),
        # over the stations looking at the area, as designer plan (a principal ray past
        # the terrain's edge meets its side far away)
        gsd_median_m=s["gsd_centre_m_median"],
        front_overlap_median=s["front_overlap_median"], front_overlap_p05=s["front_overlap_p05"],
        side_overlap_median=s["side_overlap_median"], side_overlap_p05=s["side_overlap_p05"],
        images_over_area=int(s["stations_over_area"]),
        # the declared terrain, not its surroundings
        images_over_terrain=int(np.count_nonzero(hf.contains(centre[:, 0], centre[:, 1]))),
        terrain_share=share, image_names=names, gcp_ids=ids, gcp_images=gcp_images,
        area_seen=dict(analysis.coverage.shares))
    from designer.scene.surroundings import surroundings_mode

    warn = _warnings({**figures, "surroundings": surroundings_mode(project.scene.terrain)},
                     plan)
    # the network against what SfM needs, as designer check says it (in the window's words)
    warn += [f"{w.message}; {w.panel_fix or w.fix}" for w in network_warnings(
        project, len(images.stations),
        [images.platform[k].line_index for k in images.station_index])]
    warn += _gcp_warnings(ids, gcp_images)
    check()
    finest = (finest_gsd_m(project, hf, images, terrain.raycaster) if len(images.stations)
              else float("nan"))
    return PlanFigures(**figures, warnings=tuple(warn),
                       gcp_image_index=seen.gcp_image_index, gcp_uv_px=seen.gcp_uv_px,
                       finest_gsd_m=finest)


def with_targets(figures: PlanFigures, project: m.Project, terrain, targets_result,
                 images=None) -> PlanFigures:
    """``figures`` with the GCP part (ids, images per GCP, where, the warning about GCPs
    seen by too few images) counted anew for ``project``'s targets, the flight's part
    kept: a moved, added or deleted GCP changes no image. Tens of milliseconds, so a
    GCP edit is counted as it is made. ``images``: the project's images
    (``project_images``) the figures were computed for, when the caller has them (the
    flight is then not planned again: a tenth of a second at survey size)."""
    from designer.survey.gcp_sightings import project_gcp_visibility
    from designer.survey.project_poses import project_images

    hf = terrain.heightfield
    if targets_result is None or not len(targets_result.ids):
        ids, index, uv = (), (), ()
    else:
        ids = tuple(targets_result.ids)
        if images is None:
            images = project_images(project, hf)
        vis = project_gcp_visibility(project, images, targets_result.true_xyz,
                                     terrain.raycaster)
        index, uv = vis.images, vis.uv_px
    gcp_images = np.array([len(k) for k in index], dtype=int)
    old = _gcp_warnings(figures.gcp_ids, figures.gcp_images)
    warn = [w for w in figures.warnings if w not in old] + _gcp_warnings(ids, gcp_images)
    return dataclasses.replace(figures, gcp_ids=ids, gcp_images=gcp_images,
                               gcp_image_index=index, gcp_uv_px=uv, warnings=tuple(warn))


@dataclass(frozen=True, eq=False)
class RenderedImages:
    """What each rendered image (every camera of a rig, in render order) sees."""

    names: tuple[str, ...]                     # (M,)
    terrain_share: np.ndarray                  # (M,) share of the picture on the terrain
    gcp_image_index: tuple[np.ndarray, ...]    # per GCP: images seeing it, ascending
    gcp_uv_px: tuple[np.ndarray, ...]          # per GCP: (n, 2) where, px of that image


def _rendered_images(project: m.Project, images, ground, raycaster,
                     gcp_xyz: np.ndarray | None) -> RenderedImages:
    """Every rendered image (``images``, ``project_images``) with its own pose and lens (a
    rig's obliques look much further than the station's planning camera, and see other
    GCPs): how much of it shows the rendered terrain (``ground``, ``image_ground``) and
    which GCPs it sees unhidden by the terrain (``raycaster``), where."""
    from designer.survey.gcp_sightings import project_gcp_visibility

    share = 1.0 - ground.void_share
    names = ground.names
    if gcp_xyz is None or not len(gcp_xyz):
        return RenderedImages(names, share, (), ())
    vis = project_gcp_visibility(project, images, gcp_xyz, raycaster)
    return RenderedImages(names, share, vis.images, vis.uv_px)


def void_text(void) -> str:
    """The warning about images that see past the terrain (a
    ``designer.survey.surroundings.VoidImages``), its fix as the Terrain panel's control
    (where ``designer plan`` names the project file's element)."""
    return void.warning("choose surroundings “auto” in the Terrain panel, or enlarge the "
                        "terrain" if void.surroundings == "none" else
                        "enlarge the terrain in the Terrain panel")


def _warnings(f: dict, plan: m.FlightPlan | None) -> list[str]:
    from designer.survey.surroundings import void_images

    out = []
    if np.isfinite(f["front_overlap_p05"]) and f["front_overlap_p05"] < LOW_FRONT_OVERLAP:
        planned = f" (planned {plan.front_overlap_percent:.0f} %)" if plan else ""
        out.append(f"low front overlap: 5 % of the images overlap the next by less than "
                   f"{_pct(f['front_overlap_p05'])}{planned}; raise the front overlap or fly "
                   "higher")
    if np.isfinite(f["side_overlap_p05"]) and f["side_overlap_p05"] < LOW_SIDE_OVERLAP:
        planned = f" (planned {plan.side_overlap_percent:.0f} %)" if plan else ""
        out.append(f"low side overlap: 5 % of the images overlap the next line by less "
                   f"than {_pct(f['side_overlap_p05'])}{planned}; raise the side overlap")
    void = void_images(f["image_names"], 1.0 - f["terrain_share"], f["surroundings"])
    if void is not None:
        out.append(void_text(void))
    return out


def _gcp_warnings(gcp_ids, gcp_images) -> list[str]:
    few = [g for g, n in zip(gcp_ids, gcp_images, strict=True) if n < MIN_GCP_IMAGES]
    if not few:
        return []
    return [f"GCPs seen by fewer than {count(MIN_GCP_IMAGES, 'image')}: {', '.join(few)}"]
