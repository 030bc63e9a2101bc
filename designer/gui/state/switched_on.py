"""What a switched-off setting's greyed fields show: the values switching it on gives
(docs/gui.md, "Greyed fields"), never what the fields held last or their minimum — the
flight plan a project of imported photos gets when a grid field is edited, the plant
group switching plants on makes."""

from __future__ import annotations

from designer.errors import DesignerError
from designer.gui.state import edits
from designer.project import model as m

#: the density a new group gets: plants per m²
NEW_DENSITY_PER_M2 = {"grass-tuft": 2.0, "shrub": 0.05, "tree": 0.005}
#: a new group's height spread, as a share of its mean height
NEW_HEIGHT_SD = 0.15
#: the kind of the group switching plants on makes (the Vegetation panel's check box),
#: which its fields show, greyed, while there is none
FIRST_PLANT_KIND = "shrub"


def new_plant_group(kind: str) -> m.PlantGroup:
    """A group of ``kind`` at its default size and density, sizes written out."""
    height, crown = m.PLANT_KINDS[kind]
    return m.PlantGroup(NEW_DENSITY_PER_M2[kind], kind, height_m=height,
                        height_sd_m=round(NEW_HEIGHT_SD * height, 3), crown_m=crown)


def switched_on_flight(project: m.Project) -> m.Project:
    """The project with the flight plan editing a grid field gives it (its own when it
    has one)."""
    return edits.ensure_flight_plan(project)


def flight_gsd_cm(project: m.Project) -> float | None:
    """The GSD (cm) of the project's flight plan: given, or the one its height gives
    with its camera; None without a plan or a camera the plan can use."""
    from designer.project.interiors import interior_from_camera
    from designer.survey.flight import camera_calc

    plan = project.trajectory.flight_plan
    if plan is None:
        return None
    if plan.gsd_m is not None:
        return 100 * plan.gsd_m
    try:
        interior = interior_from_camera(project.camera(plan.camera))
        calc = camera_calc(interior, altitude_agl_m=plan.altitude_agl_m,
                           front_overlap_fraction=plan.front_overlap_percent / 100,
                           side_overlap_fraction=plan.side_overlap_percent / 100)
    except (DesignerError, KeyError, ValueError):
        return None
    return 100 * calc.gsd_m
