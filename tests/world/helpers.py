"""Small projects with a flight time line and a sun over time."""

from __future__ import annotations

from dataclasses import replace

from designer.project import model as m
from tests.synthetic import small_survey

#: a site in UTM zone 32N (about 46.9° N, 9.0° E)
ORIGIN = (500000.0, 5200000.0, 400.0)
TAKEOFF = "2026-06-21T06:00:00Z"


def timed_survey(times_s=(0.0, 7200.0), sun_over_time=True, **changes) -> m.Project:
    """Two nadir photos 30 m above the same spot, taken ``times_s`` after take-off."""
    p = small_survey(origin=ORIGIN, n_photos=len(times_s), samples=2, size_px=(160, 120),
                     **changes)
    E0, N0, H0 = ORIGIN
    photos = tuple(m.ExteriorOrientation(f"IMG_{k:03d}.png", "cam", E0, N0, H0 + 30.0,
                                         0.0, 0.0, 0.0, t) for k, t in enumerate(times_s))
    lighting = m.Lighting(m.SunOverTime()) if sun_over_time else p.scene.lighting
    return replace(p, trajectory=m.Trajectory(photos, None, m.TimeLine(TAKEOFF, 5.0, 8.0)),
                   scene=replace(p.scene, lighting=lighting))
