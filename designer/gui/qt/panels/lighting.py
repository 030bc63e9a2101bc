"""Lighting: the sun (a direction, or computed for a moment and a place) and the strengths
of sun and sky. The 3D view draws the terrain and objects under this light, as the
renderer bakes it (Lambert sun with cast shadows plus an isotropic sky)."""

from __future__ import annotations

import dataclasses
import math

from PySide6.QtWidgets import QGroupBox, QLabel, QLineEdit

from designer.errors import DesignerError
from designer.gui.qt.boxes import checked_group, readouts, wrapped_label
from designer.gui.qt.panels.base import ERROR_STYLE, Panel
from designer.gui.qt.photo_selection import FOLLOW_SELECTION
from designer.gui.qt.widgets import combo, declared_field, dspin, form
from designer.gui.state import derived, edits
from designer.project import model as m
from designer.project.declare import declared_field as declared
from designer.project.declare import switched_on

SUN = "scene.lighting.sun"
CLOUDS = "scene.lighting.clouds"
#: the cloud shadows a project gets when they are switched on in the panel
DEFAULT_CLOUDS = switched_on(m.CloudShadows)
#: a moment and place to start from when the sun is switched to "computed"
DEFAULT_SUN_POSITION = m.SunPosition("2024-06-21T11:00:00+02:00", 47.37, 8.54)
#: a sun that follows the time line while the flight has none: where to switch it on
NO_TIME_LINE = ("the sun follows the flight's time line, which is off: switch it on in the "
                "Flight panel (time line: “the photos have times”), or give the sun "
                "by its direction or a moment and place above")
_KIND = {m.Sun: "direction", m.SunPosition: "position", m.SunOverTime: "over-time"}


class LightingPanel(Panel):
    title = "Lighting"
    # the sun over time and the clouds follow the time line (Flight panel)
    parts = frozenset({"lighting", "trajectory"})

    def build(self, layout) -> None:
        top = form()
        self.kind = combo([("direction (azimuth, elevation)", "direction"),
                           ("computed for a date, time and place", "position"),
                           ("following the flight's time line", "over-time")])
        self.kind.currentIndexChanged.connect(self._kind_chosen)
        top.addRow("sun given by", self.kind)
        layout.addLayout(top)

        self.direction = QGroupBox("sun direction")
        f = form(self.direction)
        f.addRow("azimuth", self.bindings.bind(
            declared_field(m.Sun, "azimuth_deg"), f"{SUN}.azimuth_deg", "Sun azimuth"))
        f.addRow("elevation", self.bindings.bind(
            declared_field(m.Sun, "elevation_deg"), f"{SUN}.elevation_deg", "Sun elevation"))
        note = QLabel("azimuth clockwise from grid north; elevation above the horizon")
        note.setWordWrap(True)
        f.addRow(note)
        layout.addWidget(self.direction)

        self.position = QGroupBox("sun computed for")
        f = form(self.position)
        self.date_time = QLineEdit()
        self.date_time.setPlaceholderText("2024-06-21T11:00:00+02:00")
        f.addRow("date, time", self.bindings.bind(self.date_time, f"{SUN}.date_time",
                                                  "Sun date and time"))
        f.addRow("latitude", self.bindings.bind(
            declared_field(m.SunPosition, "latitude_deg"), f"{SUN}.latitude_deg",
            "Sun latitude"))
        f.addRow("longitude", self.bindings.bind(
            declared_field(m.SunPosition, "longitude_deg"), f"{SUN}.longitude_deg",
            "Sun longitude"))
        note = QLabel("ISO 8601 with a time zone; the azimuth is from true north (add the "
                      "grid convergence of a projected CRS yourself)")
        note.setWordWrap(True)
        f.addRow(note)
        layout.addWidget(self.position)

        strengths = QGroupBox("strengths")
        f = form(strengths)
        f.addRow("sun", self.bindings.bind(dspin(0, 1000, 2, 0.5), "scene.lighting.sun_strength",
                                           "Sun strength"))
        f.addRow("sky", self.bindings.bind(dspin(0, 1000, 2, 0.25),
                                           "scene.lighting.sky_strength", "Sky strength"))
        layout.addWidget(strengths)

        clouds, f, self.cloudy = checked_group(
            "cloud shadows", "drifting cloud shadows", self._clouds_toggled,
            "a seeded field of cloud shadows drifting with the wind over the flight's time "
            "line; they dim the direct sun (docs/world.md)")
        for name, undo in (("cover", "Cloud cover"), ("size_m", "Cloud size"),
                           ("softness_m", "Cloud edge softness"), ("depth", "Cloud shadow depth"),
                           ("wind_speed_m_s", "Wind speed"),
                           ("wind_direction_deg", "Wind direction"), ("seed", "Cloud seed")):
            f.addRow(declared(m.CloudShadows, name).label, self.bindings.bind(
                declared_field(m.CloudShadows, name), f"{CLOUDS}.{name}", undo))
        self.clouds_note = QLabel()
        self.clouds_note.setWordWrap(True)
        f.addRow(self.clouds_note)
        self.cloud_moment = combo([])
        self.cloud_moment.setObjectName("cloud-moment")
        self.cloud_moment.setToolTip(
            "the moment of the flight the 3D view draws the cloud shadows at, on the ground, "
            "buildings and objects: by default the selected photo's (click a camera station "
            "in the view or a thumbnail in the Render panel; none selected: the flight's "
            "start); the flight's start or a photo chosen here stays, whatever photo is "
            "selected, until “the selected photo” is chosen again; a photo chosen here is "
            "selected too")
        self.cloud_moment.currentIndexChanged.connect(
            lambda _i: self.sync.set_cloud_moment(self.cloud_moment.currentData()))
        f.addRow("drawn at", self.cloud_moment)
        layout.addWidget(clouds)
        self.sync.stations_changed.connect(self._fill_moments)
        self.sync.photo_selected.connect(lambda _k: self._name_selected_photo())
        self._fill_moments()

        self.sun_label, self.contrast_label = readouts(layout, "sun", "shadows")
        self.error_label = wrapped_label(ERROR_STYLE)
        layout.addWidget(self.error_label)

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        super().refresh()
        sun = self.project.scene.lighting.sun
        computed = isinstance(sun, m.SunPosition)
        blocked = self.kind.blockSignals(True)
        self.kind.setCurrentIndex(self.kind.findData(_KIND[type(sun)]))
        self.kind.blockSignals(blocked)
        self.direction.setVisible(isinstance(sun, m.Sun))
        self.position.setVisible(computed)
        clouds = self.project.scene.lighting.clouds
        blocked = self.cloudy.blockSignals(True)
        self.cloudy.setChecked(clouds is not None)
        self.cloudy.blockSignals(blocked)
        self.cloud_moment.setEnabled(clouds is not None)
        self.clouds_note.setText(
            "" if clouds is None else
            "they drift with each photo's time" if self.project.trajectory.time_line else
            "no time line: every photo sees the shadows as at take-off")
        self._readouts()

    def _readouts(self) -> None:
        lighting = self.project.scene.lighting
        if isinstance(lighting.sun, m.SunOverTime) and self.project.trajectory.time_line is None:
            self.sun_label.setText("–")
            self.contrast_label.setText("–")
            self.error_label.setText(NO_TIME_LINE)
            return
        try:
            azimuth, elevation = derived.sun_angles_deg(lighting, self.project)
        except (DesignerError, ValueError) as error:
            self.sun_label.setText("–")
            self.contrast_label.setText("–")
            self.error_label.setText(str(error))
            return
        self.error_label.setText("" if elevation > 0 else
                                 "the sun is below the horizon at that moment and place")
        where = {m.SunPosition: " (computed)", m.SunOverTime: " at take-off; it moves "
                 "with each photo's time"}.get(type(lighting.sun), "")
        self.sun_label.setText(f"azimuth {azimuth:.1f}°, elevation {elevation:.1f}°{where}")
        flat = lighting.sun_strength * max(math.sin(math.radians(elevation)), 0.0) + \
            lighting.sky_strength
        if flat > 0:
            self.contrast_label.setText(
                f"flat ground in shadow gets {100 * lighting.sky_strength / flat:.0f} % of "
                "the light of flat ground in full sun")
        else:
            self.contrast_label.setText("no light at all: raise the sun or sky strength")

    def _fill_moments(self) -> None:
        """The moments the view can draw the cloud shadows at: the selected photo's, the
        flight's start, then each photo at its time on the time line (none without one:
        every photo sees them as at take-off)."""
        times = self.sync.station_times()
        box, chosen = self.cloud_moment, self.sync.cloud_moment
        blocked = box.blockSignals(True)
        box.clear()
        box.addItem("", FOLLOW_SELECTION)
        box.addItem("the flight's start", None)
        for k, t in enumerate(times or ()):
            box.addItem(f"{t.image_name} ({t.time_s:.0f} s after take-off)", k)
        index = box.findData(chosen) if chosen is not None else 1
        box.setCurrentIndex(max(index, 0))
        box.blockSignals(blocked)
        self._name_selected_photo()
        if index < 0:
            self.sync.set_cloud_moment(FOLLOW_SELECTION)  # that photo is gone

    def _name_selected_photo(self) -> None:
        """The first entry of "drawn at" names the selected photo and its moment."""
        k, stations = self.sync.selected_photo, self.sync.stations
        if k is None or stations is None or k >= len(stations.stations):
            text = "the selected photo (none yet: the flight's start)"
        else:
            times = self.sync.station_times()
            when = ("no time line: as at take-off" if times is None else
                    f"{times[k].time_s:.0f} s")
            text = f"the selected photo: {stations.stations[k].image_name} ({when})"
        self.cloud_moment.setItemText(0, text)

    # ------------------------------------------------------------------ view → model
    def _clouds_toggled(self, on: bool) -> None:
        if on == (self.project.scene.lighting.clouds is not None):
            return
        self.editor.edit(edits.replace_path(self.project, CLOUDS, DEFAULT_CLOUDS if on else None),
                         "Cloud shadows " + ("on" if on else "off"))

    def _kind_chosen(self) -> None:
        lighting = self.project.scene.lighting
        kind = self.kind.currentData()
        if kind == _KIND[type(lighting.sun)]:
            return
        if kind == "position":
            sun = DEFAULT_SUN_POSITION
        elif kind == "over-time":
            sun = _sun_over_time(self.project)
        else:
            # keep the light where it was: the computed direction, rounded to 0.1°
            try:
                azimuth, elevation = derived.sun_angles_deg(lighting, self.project)
            except (DesignerError, ValueError):
                azimuth, elevation = 135.0, 50.0
            sun = m.Sun(round(azimuth % 360, 1) % 360, round(min(max(elevation, 0.1), 90), 1))
        scene = dataclasses.replace(self.project.scene,
                                    lighting=dataclasses.replace(lighting, sun=sun))
        self.editor.edit(dataclasses.replace(self.project, scene=scene),
                         "Sun " + {"position": "computed for a moment and place",
                                   "over-time": "following the flight's time line"}.get(
                                       kind, "given by its direction"))


def _sun_over_time(project: m.Project) -> m.SunOverTime:
    """A sun over time at the project origin, or at the default place when the project's
    CRS cannot give the origin's latitude and longitude."""
    from designer.scene.sun_over_time import project_site

    try:
        project_site(project, m.SunOverTime())
        return m.SunOverTime()
    except DesignerError:
        return m.SunOverTime(DEFAULT_SUN_POSITION.latitude_deg,
                             DEFAULT_SUN_POSITION.longitude_deg)
