"""The selected photo and the moment the 3D view draws the cloud shadows at.

A photo is selected by clicking its camera station in the 3D view or its thumbnail in
the Render panel; the view marks its station and the status bar names it. The cloud
shadows drift with the wind over the flight's time line, so the view draws them at one
moment, the Lighting panel's "drawn at": by default the selected photo's (the flight's
start while none is selected), or a moment the user chose there — the flight's start or
one photo — which then stays whatever photo is selected. A photo chosen there is selected
too, as if its station had been clicked.

Mixed into :class:`~designer.gui.qt.scene_sync.SceneSync`, which holds the stations, the
view and the ``photo_selected`` and ``message`` signals.
"""

from __future__ import annotations

from designer.errors import DesignerError

#: "drawn at" following the selected photo (the default)
FOLLOW_SELECTION = "selected photo"
#: a click this close (px) to a station's perspective centre selects its photo
STATION_GRAB_PX = 10.0


class PhotoSelection:
    """The selected photo and the cloud shadows' moment (a mixin of SceneSync)."""

    def _init_photo_selection(self) -> None:
        #: the station (index into ``stations.stations``) whose photo is selected, or None
        self.selected_photo: int | None = None
        #: what the cloud shadows are drawn at: FOLLOW_SELECTION, None (the flight's
        #: start) or a station index
        self.cloud_moment: int | str | None = FOLLOW_SELECTION
        self.view.clicked.connect(self._view_clicked)

    @property
    def cloud_station(self) -> int | None:
        """The station whose moment the cloud shadows are drawn at (None: the flight's
        start)."""
        if self.cloud_moment == FOLLOW_SELECTION:
            return self.selected_photo
        return self.cloud_moment

    def station_times(self):
        """Each station's StationTime (designer.survey.timeline), or None without a time
        line or stations."""
        from designer.survey.timeline import project_station_times

        if self.stations is None or not self.stations.stations:
            return None
        try:
            return project_station_times(self.document.project, self.stations.stations)
        except DesignerError:
            return None

    def cloud_time_s(self) -> float:
        """Seconds after take-off the cloud shadows are drawn at (the render drifts them
        with the wind over the flight's time line): the chosen station's time, or 0, the
        flight's start, with none chosen or photos without times."""
        k, times = self.cloud_station, self.station_times()
        if k is None or times is None or not 0 <= k < len(times):
            return 0.0
        return times[k].time_s

    def set_cloud_moment(self, moment: int | str | None) -> None:
        """Draw the cloud shadows at ``moment``: FOLLOW_SELECTION, None (the flight's
        start) or a station index, whose photo is then selected as well (the moment
        stays that station's, not the selection's)."""
        self.cloud_moment = moment
        if self.document.project.scene.lighting.clouds is not None:
            self.refresh_cloud_shadows()
        self.refresh_moving()
        if isinstance(moment, int) and moment != self.selected_photo:
            self.select_photo(moment)

    def select_photo(self, index: int | None) -> None:
        """Select station ``index``'s photo (None: none): marked in the view, named in
        the status bar, and the cloud shadows drawn at its moment while "drawn at"
        follows the selection."""
        stations = self.stations
        if stations is None or index is None or not 0 <= index < len(stations.stations):
            index = None
        before = self.cloud_time_s()
        self.selected_photo = index
        self._mark_selected_photo()
        self.photo_selected.emit(index)
        if index is not None:
            self.message.emit(self._photo_text(index))
        if self.cloud_time_s() != before:
            if self.document.project.scene.lighting.clouds is not None:
                self.refresh_cloud_shadows()
            self.refresh_moving()  # the objects stand where they are at that moment

    def _photo_text(self, index: int) -> str:
        name = self.stations.stations[index].image_name
        times = self.station_times()
        when = "" if times is None else f", {times[index].time_s:.0f} s after take-off"
        clouds = (self.document.project.scene.lighting.clouds is not None
                  and self.cloud_station == index)
        return (f"photo {name} selected (station {index + 1} of "
                f"{len(self.stations.stations)}{when})"
                + ("; the cloud shadows are drawn at its moment" if clouds else ""))

    def _mark_selected_photo(self) -> None:
        k, stations = self.selected_photo, self.stations
        if k is None or stations is None:
            self.view.show_selected_station(None)
        else:
            self.view.show_selected_station(stations.C_world[k],
                                            stations.stations[k].image_name)

    def _view_clicked(self, x_px: float, y_px: float) -> None:
        """A click in the view near a station's perspective centre selects its photo."""
        if self.stations is None or not len(self.stations.C_world):
            return
        k = self.view.point_near(self.stations.C_world, x_px, y_px, STATION_GRAB_PX)
        if k is not None:
            self.select_photo(k)

    def photo_of_image(self, image_name: str) -> int | None:
        """The station whose photo (or, with a rig, one of whose photos) is the rendered
        image ``image_name``, or None when the stations have no such image."""
        from designer.core.rig import mount_image_name

        stations = self.stations
        if stations is None:
            return None
        suffixes = [mount.suffix for rig in self.document.project.trajectory.rigs
                    for mount in rig.mounts]
        names = {}
        for k, st in enumerate(stations.stations):
            for suffix in suffixes:
                names.setdefault(mount_image_name(st.image_name, suffix), k)
        names.update({st.image_name: k for k, st in enumerate(stations.stations)})
        return names.get(image_name)

    def _stations_replaced(self) -> None:
        """New stations: a selected photo that is gone goes, a photo chosen in "drawn at"
        that is gone gives way to the selected photo, and the others are drawn again
        where and when they are now."""
        n = len(self.stations.stations) if self.stations is not None else 0
        if isinstance(self.cloud_moment, int) and self.cloud_moment >= n:
            self.cloud_moment = FOLLOW_SELECTION
        if self.selected_photo is not None and self.selected_photo >= n:
            self.selected_photo = None
            self.photo_selected.emit(None)
        self._mark_selected_photo()
        if self.cloud_station is not None:  # its moment may have moved
            if self.document.project.scene.lighting.clouds is not None:
                self.refresh_cloud_shadows()
            self.refresh_moving()
