"""Processing settings of a reconstruction and the simulated inputs they ask for.

The settings are the project's ``<processing>`` (read through the render output's
``manifest.json``, or given), with command-line overrides. The simulated inputs —
marking errors of the target image positions, in-flight camera positions with GNSS or
RTK errors, a pre-calibration that differs from the true camera — are drawn here from
their seeds, so the same settings always give the same inputs.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from designer.core.truth import GcpObservation, GroundControlPoint
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.declare import declared_field

#: FULL_OPENCV parameter order: fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6
PARAM_NAMES = ("fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6")
#: indices of the FULL_OPENCV parameters each calibration mode estimates
VARIABLE_PARAMS = {
    "fixed": (),
    "focal": (0, 1),
    "focal-principal-point": (0, 1, 2, 3),
    "radial": (0, 1, 2, 3, 4, 5, 8),
    "full": (0, 1, 2, 3, 4, 5, 6, 7, 8),
}


def project_of_survey(survey: Path) -> Path | None:
    """The project file a render output was made from (``manifest.json``), if it exists."""
    manifest = Path(survey) / "manifest.json"
    if not manifest.is_file():
        return None
    try:
        path = Path(json.loads(manifest.read_text())["project"])
    except (ValueError, KeyError, TypeError):
        return None
    return path if path.is_file() else None


def resolve_processing(survey: Path, project: Path | None = None, *,
                       calibration: str | None = None, gcps: str | None = None,
                       marking_sigma_px: float | None = None,
                       position_prior: str | None = None, dense: str | None = None,
                       max_features: int | None = None, sift_scale: str | None = None,
                       pairs: str | None = None,
                       min_track_length: int | None = None,
                       control_ids: tuple[str, ...] | None = None,
                       control_count: int | None = None,
                       control_spread: str | None = None,
                       rolling_shutter: str | None = None,
                       mapper: str | None = None,
                       global_adjustment_growth: float | None = None) -> m.Processing:
    """The project's ``<processing>`` (defaults when absent) with the given overrides."""
    base = m.Processing()
    path = project or project_of_survey(survey)
    if path is not None:
        from designer.project.load import load_project

        base = load_project(path).processing or m.Processing()
    p = base
    if calibration is not None:
        p = dataclasses.replace(p, calibration=dataclasses.replace(p.calibration,
                                                                   mode=calibration))
    if rolling_shutter is not None:
        p = dataclasses.replace(p, calibration=dataclasses.replace(
            p.calibration, rolling_shutter=rolling_shutter))
    g = p.gcps
    if gcps is not None:
        g = dataclasses.replace(g, mode=gcps)
    if marking_sigma_px is not None:
        g = dataclasses.replace(g, marking_sigma_px=marking_sigma_px)
    if control_ids is not None or control_count is not None:
        g = dataclasses.replace(g, control=m.ControlSelection(
            tuple(control_ids or ()), control_count, control_spread or "even"))
    p = dataclasses.replace(p, gcps=g)
    if position_prior is not None:
        p = dataclasses.replace(p, position_prior=dataclasses.replace(
            p.position_prior, mode=position_prior))
    mt = p.matching
    for name, value in (("max_features", max_features), ("sift_scale", sift_scale),
                        ("pairs", pairs), ("min_track_length", min_track_length)):
        if value is not None:
            mt = dataclasses.replace(mt, **{name: value})
    p = dataclasses.replace(p, matching=mt)
    if dense is not None:
        p = dataclasses.replace(p, dense=dense)
    if mapper is not None:
        p = dataclasses.replace(p, sfm=dataclasses.replace(p.sfm, mapper=mapper))
    if global_adjustment_growth is not None:
        p = dataclasses.replace(p, sfm=dataclasses.replace(
            p.sfm, global_adjustment_growth=global_adjustment_growth))
    check_processing(p)
    return p


def check_processing(p: m.Processing) -> None:
    """One-line DesignerError for settings no reconstruction can use."""
    marking = declared_field(m.GcpProcessing, "marking_sigma_px")  # the one range
    if not marking.in_range(p.gcps.marking_sigma_px):
        raise DesignerError(f"--marking-sigma-px {p.gcps.marking_sigma_px}: give a marking "
                            f"error of 0 (ideal) or more, {marking.range_text()}")
    h, v = p.position_prior.sigmas_m
    if p.position_prior.mode != "none" and not (h > 0 and v > 0):
        raise DesignerError(f"position prior sigma {h} m / {v} m: standard deviations must "
                            "be greater than 0")
    track = declared_field(m.Matching, "min_track_length")
    if not track.in_range(p.matching.min_track_length):
        raise DesignerError(f"--min-track-length {p.matching.min_track_length}: use "
                            f"{track.range_text()}")
    growth = declared_field(m.Sfm, "global_adjustment_growth")
    if not growth.in_range(p.sfm.global_adjustment_growth):
        raise DesignerError(f"--global-adjustment-growth {p.sfm.global_adjustment_growth}: "
                            f"use {growth.range_text()}")
    if not 100 <= p.matching.max_features <= 1_000_000:
        raise DesignerError(f"--max-features {p.matching.max_features}: use 100 to 1000000")
    if p.calibration.rolling_shutter not in ("none", "compensate"):
        raise DesignerError(f"--rolling-shutter {p.calibration.rolling_shutter}: use none or "
                            "compensate")
    if p.calibration.mode not in VARIABLE_PARAMS:
        raise DesignerError(f"--calibration {p.calibration.mode}: use one of "
                            f"{', '.join(VARIABLE_PARAMS)}")


def marked_observations(observations: list[GcpObservation], sigma_px: float,
                        seed: int) -> list[GcpObservation]:
    """Target image positions as an operator marks them: + N(0, σ²) px per axis."""
    if sigma_px <= 0:
        return list(observations)
    rng = np.random.default_rng(seed)
    noise = rng.normal(0.0, sigma_px, size=(len(observations), 2))
    return [GcpObservation(o.gcp_id, o.image_name, np.asarray(o.uv_px) + d)
            for o, d in zip(observations, noise, strict=True)]


def flight_positions(C_world: np.ndarray, sigma_h_m: float, sigma_v_m: float,
                     seed: int) -> np.ndarray:
    """Measured camera centres (N, 3, world m): true + N(0, σh²) on X, Y, N(0, σv²) on Z."""
    rng = np.random.default_rng(seed)
    sigma = np.array([sigma_h_m, sigma_h_m, sigma_v_m])
    return np.asarray(C_world, float) + rng.normal(size=np.shape(C_world)) * sigma


def start_params(true_params: np.ndarray, pre: m.PreCalibrationError | None) -> np.ndarray:
    """FULL_OPENCV starting parameters: the truth plus the seeded pre-calibration error
    (one focal error for fx and fy, so the aspect stays)."""
    params = np.array(true_params, dtype=float)
    if pre is None:
        return params
    rng = np.random.default_rng(pre.seed)
    e = rng.normal(size=7) * np.array([pre.focal_px, pre.principal_point_px,
                                       pre.principal_point_px, pre.k1, pre.k2, pre.k3, pre.p1])
    e_p2 = rng.normal() * pre.p2
    params[0:2] += e[0]
    params[2:4] += e[1:3]
    params[4:6] += e[3:5]
    params[8] += e[5]
    params[6] += e[6]
    params[7] += e_p2
    return params


def control_ids(gcps: list[GroundControlPoint], selection: m.ControlSelection | None,
                source: str = "--control") -> set[str]:
    """Ids of the control points: the targets' roles, a list, or k of n spread evenly
    (farthest-point order from the corner farthest from the centre) or at random."""
    ids = [g.gcp_id for g in gcps]
    if selection is None:
        return {g.gcp_id for g in gcps if g.role == "control"}
    if selection.ids:
        unknown = [i for i in selection.ids if i not in ids]
        if unknown:
            raise DesignerError(f"{source}: unknown GCP id {unknown[0]!r}; the survey has "
                                f"{', '.join(ids) or 'no GCPs'}")
        return set(selection.ids)
    k = selection.count or 0
    if not 1 <= k <= len(ids):
        raise DesignerError(f"{source}: {k} control points of {len(ids)} GCPs; choose 1 to "
                            f"{len(ids)}")
    if selection.spread == "random":
        rng = np.random.default_rng(selection.seed)
        return {ids[i] for i in rng.choice(len(ids), size=k, replace=False)}
    xy = np.array([g.true_xyz[:2] for g in gcps])
    chosen = [int(np.argmax(((xy - xy.mean(axis=0)) ** 2).sum(axis=1)))]
    while len(chosen) < k:
        d = np.min(((xy[:, None, :] - xy[chosen][None, :, :]) ** 2).sum(axis=-1), axis=1)
        chosen.append(int(np.argmax(d)))
    return {ids[i] for i in chosen}


def settings_dict(p: m.Processing) -> dict:
    """The settings as plain JSON values (for summary.json)."""
    out = dataclasses.asdict(p)
    out["position_prior"]["sigmas_m"] = list(p.position_prior.sigmas_m)
    return out
