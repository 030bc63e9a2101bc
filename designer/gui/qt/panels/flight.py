"""Flight: area (drawn on the terrain or typed), altitude or GSD, overlaps, angle,
crosshatch, terrain following, tilt, pose noise; image count and render time live."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtWidgets import (
    QButtonGroup,
    QCheckBox,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPushButton,
    QRadioButton,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from designer.gui.qt.boxes import checked_group, wrapped_label
from designer.gui.qt.panels.base import ERROR_STYLE, Panel
from designer.gui.qt.widgets import combo, declared_field, dspin, form, ispin, model_getter, readout
from designer.gui.state import derived, edits
from designer.gui.state.switched_on import flight_gsd_cm, switched_on_flight
from designer.gui.state.wording import count
from designer.project import model as m

FP = "trajectory.flight_plan"
#: the box of the figures over the real terrain
REAL_TITLE = "over the real terrain (as designer plan measures it)"
#: what the box says while its figures are computed
COMPUTING = "being computed…"
#: the rig mount table: (header, Mount field or "rig")
MOUNT_COLUMNS = (("rig", "rig"), ("camera", "camera"), ("suffix", "suffix"),
                 ("ω °", "omega_deg"), ("φ °", "phi_deg"), ("κ °", "kappa_deg"))


#: the "grid" readout of a flight of photos listed one by one
NO_GRID = ("none: the photos are listed one by one (imported or explicit); “Add a grid "
           "flight over the terrain” plans one")


class FlightPanel(Panel):
    title = "Flight"
    parts = frozenset({"trajectory", "cameras", "render"})

    def build(self, layout) -> None:
        self.create = QPushButton("Add a grid flight over the terrain")
        self.create.clicked.connect(lambda: self.editor.edit(
            edits.ensure_flight_plan(self.project, self._mesh_reference_m()),
            "Add flight plan"))
        layout.addWidget(self.create)

        # the figures and warnings that grow and shrink as the flight changes are in a
        # pane of their own below the fields (build_figures): they move no field
        area = QGroupBox("area (world X, Y; m)")
        box = form(area)
        row = QHBoxLayout()
        self.draw = QPushButton("Draw on terrain")
        self.draw.setCheckable(True)
        self.draw.setToolTip("Click the vertices on the terrain; double-click, right-click "
                             "or Enter to close, Esc to cancel")
        self.draw.toggled.connect(self._draw_toggled)
        whole = QPushButton("Whole terrain")
        whole.clicked.connect(lambda: self.set_area(edits.terrain_rectangle(self.project)))
        row.addWidget(self.draw)
        row.addWidget(whole)
        box.addRow(row)
        self.area_table = QTableWidget(0, 2)
        self.area_table.setHorizontalHeaderLabels(["X", "Y"])
        self.area_table.setMinimumHeight(160)  # four rows whole: a square area
        self.area_table.setMaximumHeight(170)
        self.area_table.itemChanged.connect(self._area_typed)
        box.addRow(self.area_table)
        layout.addWidget(area)

        grid = QGroupBox("grid")
        f = form(grid)
        self.camera = combo([])
        self.bindings.bind(self.camera, f"{FP}.camera", "Flight camera")
        f.addRow("camera", self.camera)
        self.by_altitude = QRadioButton("height above ground")
        self.by_gsd = QRadioButton("ground sample distance")
        group = QButtonGroup(self)
        group.addButton(self.by_altitude)
        group.addButton(self.by_gsd)
        self.by_altitude.toggled.connect(self._height_mode)
        self.altitude_spin = self.bindings.bind(
            dspin(0.1, 1e5, 2, 5, "m"), f"{FP}.altitude_agl_m", "Height above ground")
        self.gsd_spin = self.bindings.bind(dspin(0.001, 1000, 3, 0.1, "cm"), (
            model_getter(f"{FP}.gsd_m", lambda v: None if v is None else 100 * v),
            lambda p, v: edits.set_flight(p, gsd_m=v / 100)), "Flight GSD")
        f.addRow(self.by_altitude, self.altitude_spin)
        f.addRow(self.by_gsd, self.gsd_spin)
        for label, field, box_ in (
                ("front overlap", "front_overlap_percent", dspin(0, 99, 1, 5, "%")),
                ("side overlap", "side_overlap_percent", dspin(0, 99, 1, 5, "%")),
                ("line azimuth", "grid_angle_deg", dspin(-360, 360, 1, 5, "°")),
                ("forward tilt", "tilt_deg", dspin(-80, 80, 1, 5, "°"))):
            f.addRow(label, self.bindings.bind(box_, f"{FP}.{field}", f"Flight {label}"))
        f.addRow("", self.bindings.bind(QCheckBox("crosshatch (second grid at 90°)"),
                                        f"{FP}.crosshatch", "Crosshatch"))
        f.addRow("", self.bindings.bind(QCheckBox("terrain following"),
                                        f"{FP}.terrain_following", "Terrain following"))
        f.addRow("altitude above", self.bindings.bind(
            combo([("mean terrain", "mean"), ("highest terrain", "max"),
                   ("lowest terrain", "min"), ("a given height", "given")]), (
                model_getter(f"{FP}.altitude_reference", _reference_kind),
                lambda p, v: edits.set_flight(p, altitude_reference=(
                    v if v != "given" else self._given_reference_m()))),
            "Altitude reference"))
        f.addRow("given height", self.bindings.bind(dspin(-1e4, 1e5, 3, 1, "m"), (
            model_getter(f"{FP}.altitude_reference",
                         lambda v: None if isinstance(v, str) else v),
            lambda p, v: edits.set_flight(p, altitude_reference=float(v))),
            "Altitude reference height"))
        f.addRow("image", self.bindings.bind(
            combo([("landscape", "landscape"), ("portrait", "portrait")]),
            f"{FP}.orientation", "Image orientation"))
        f.addRow("start corner", self.bindings.bind(
            combo([(c, c) for c in ("SW", "SE", "NW", "NE")]), f"{FP}.start_corner",
            "Start corner"))
        f.addRow("image prefix", self.bindings.bind(_line(), f"{FP}.image_prefix",
                                                    "Image prefix"))
        # greyed while the photos are listed one by one (no plan): the plan editing a
        # field gives, not the fields' minimum
        for widget, get in self.bindings.items:
            if widget.objectName().startswith(f"{FP}."):
                widget.switched_on_value = (
                    lambda p, get=get: get(switched_on_flight(p)))
        self.gsd_spin.switched_on_value = lambda p: flight_gsd_cm(switched_on_flight(p))
        layout.addWidget(grid)

        rig = QGroupBox("oblique rig (cameras fired together at each station)")
        rig.setToolTip("choose the rig as the flight's camera; each mount's camera is turned "
                       "by ω φ κ relative to the platform (docs/world.md)")
        f = form(rig)
        self.add_rig = QPushButton("Add a nadir + four 45° oblique rig")
        self.add_rig.clicked.connect(lambda: self.editor.edit(
            edits.add_oblique_rig(self.project), "Add oblique rig"))
        f.addRow(self.add_rig)
        self.mount_table = QTableWidget(0, len(MOUNT_COLUMNS))
        self.mount_table.setObjectName("rig-mounts")
        self.mount_table.setHorizontalHeaderLabels([c[0] for c in MOUNT_COLUMNS])
        self.mount_table.setMinimumHeight(150)
        self.mount_table.itemChanged.connect(self._mount_typed)
        f.addRow(self.mount_table)
        layout.addWidget(rig)

        noise, f, self.noisy = checked_group(
            "pose noise (σ)", "perturb the planned poses", self._noise_toggled,
            "position σ along the world axes, angle σ about the camera axes")
        pn = f"{FP}.pose_noise"
        for label, field, unit in (("X", "sigma_X_m", "m"), ("Y", "sigma_Y_m", "m"),
                                   ("Z", "sigma_Z_m", "m"), ("ω", "sigma_omega_deg", "°"),
                                   ("φ", "sigma_phi_deg", "°"), ("κ", "sigma_kappa_deg", "°")):
            f.addRow(f"σ {label}", self.bindings.bind(dspin(0, 100, 3, 0.05, unit),
                                                      f"{pn}.{field}", f"Pose noise σ {label}"))
        f.addRow("seed", self.bindings.bind(ispin(0, 2**31 - 1), f"{FP}.random_seed",
                                            "Flight seed"))
        layout.addWidget(noise)

        timing, f, self.timed = checked_group(
            "time line (when each photo is taken)", "the photos have times",
            self._timing_toggled,
            "the first photo at take-off, then the stations in order at the speed, plus a "
            "turn time per line change (docs/world.md)")
        tl = "trajectory.time_line"
        takeoff = _line()
        takeoff.setPlaceholderText(DEFAULT_TIME_LINE.takeoff_utc)
        f.addRow("take-off (UTC)", self.bindings.bind(takeoff, f"{tl}.takeoff_utc",
                                                      "Take-off time"))
        f.addRow("speed", self.bindings.bind(declared_field(m.TimeLine, "speed_m_s"),
                                             f"{tl}.speed_m_s",
                                             "Flight speed"))
        f.addRow("turn", self.bindings.bind(declared_field(m.TimeLine, "turn_s"), f"{tl}.turn_s",
                                            "Turn time"))
        layout.addWidget(timing)

        view = self.sync.view
        view.area_drawn.connect(self.set_area)
        view.interaction.mode_changed.connect(self._mode_changed)
        self.sync.stations_changed.connect(self._readouts)
        self.sync.plan_changed.connect(self._plan_readouts)
        self.sync.plan_computing_changed.connect(self._plan_readouts)
        # what lies off the terrain file's ground moves with the GCPs, buildings and area;
        # the control's spread with the GCPs
        self.sync.terrain_changed.connect(self._show_warnings)
        self.sync.targets_changed.connect(self._show_warnings)

    def build_figures(self) -> QWidget:
        """The flight's figures (image count, GSD, footprint, render time; the GSD and
        overlaps over the real terrain) and its warnings, below the fields."""
        figures = QWidget()
        layout = QVBoxLayout(figures)
        layout.setContentsMargins(6, 6, 6, 6)
        # the warnings first: what to fix is seen without scrolling the pane
        self.warnings_label = QLabel()
        self.warnings_label.setObjectName("plan-warnings")
        self.warnings_label.setWordWrap(True)
        self.warnings_label.setStyleSheet("color: #b9770e; font-weight: bold")
        layout.addWidget(self.warnings_label)
        info = QGroupBox("what this flight delivers")
        f = form(info)
        self.images_label = readout()
        self.images_label.setStyleSheet("font-weight: bold")
        self.calc_label, self.time_label = readout(), readout()
        f.addRow("images", self.images_label)
        f.addRow("grid", self.calc_label)
        f.addRow("render time", self.time_label)
        self.error_label = wrapped_label(ERROR_STYLE)
        f.addRow(self.error_label)
        layout.addWidget(info)

        real = QGroupBox(REAL_TITLE)
        self.real_box = real
        f = form(real)
        self.real_gsd, self.real_overlap, self.real_images = readout(), readout(), readout()
        f.addRow("GSD", self.real_gsd)
        f.addRow("achieved overlap", self.real_overlap)
        f.addRow("images", self.real_images)
        layout.addWidget(real)
        layout.addStretch(1)
        return figures

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        project = self.project
        blocked = self.camera.blockSignals(True)
        self.camera.clear()
        for cam in project.cameras:
            self.camera.addItem(cam.name or cam.id, cam.id)
        for rig in project.trajectory.rigs:
            self.camera.addItem(f"rig {rig.name} ({len(rig.mounts)} cameras)", rig.name)
        self.camera.blockSignals(blocked)
        self._mounts_to_table()
        super().refresh()
        plan = project.trajectory.flight_plan
        self.create.setVisible(plan is None)
        for button in (self.by_altitude, self.by_gsd, self.noisy, self.draw):
            button.setEnabled(plan is not None)
        if plan is not None:
            _check(self.by_altitude, plan.altitude_agl_m is not None)
            _check(self.by_gsd, plan.gsd_m is not None)
            _check(self.noisy, plan.pose_noise is not None)
        _check(self.timed, project.trajectory.time_line is not None)
        self.area_table.blockSignals(True)
        area = plan.area if plan is not None else ()
        self.area_table.setRowCount(len(area))
        for r, (x, y) in enumerate(area):
            self.area_table.setItem(r, 0, QTableWidgetItem(f"{x:.3f}"))
            self.area_table.setItem(r, 1, QTableWidgetItem(f"{y:.3f}"))
        self.area_table.blockSignals(False)
        self._readouts()

    def _mounts_to_table(self) -> None:
        rows = [(r, k, rig, mount) for r, rig in enumerate(self.project.trajectory.rigs)
                for k, mount in enumerate(rig.mounts)]
        self.mount_table.blockSignals(True)
        self.mount_table.setRowCount(len(rows))
        self._mount_rows = [(r, k) for r, k, _, _ in rows]
        for row, (_, _, rig, mount) in enumerate(rows):
            for col, (_, field) in enumerate(MOUNT_COLUMNS):
                value = rig.name if field == "rig" else getattr(mount, field)
                text = f"{value:g}" if isinstance(value, float) else str(value)
                item = QTableWidgetItem(text)
                if field == "rig":
                    item.setFlags(item.flags() & ~Qt.ItemFlag.ItemIsEditable)
                self.mount_table.setItem(row, col, item)
        self.mount_table.blockSignals(False)
        self.add_rig.setVisible(not self.project.trajectory.rigs)

    def _mount_typed(self, item: QTableWidgetItem) -> None:
        """A typed mount value goes through the undo stack; a bad number is put back."""
        rig_index, mount_index = self._mount_rows[item.row()]
        field = MOUNT_COLUMNS[item.column()][1]
        text = item.text().strip()
        if field.endswith("_deg"):
            try:
                value = float(text)
            except ValueError:
                self._mounts_to_table()
                return
        else:
            value = text
        self.editor.edit(edits.set_mount(self.project, rig_index, mount_index,
                                         **{field: value}),
                         f"Rig mount {MOUNT_COLUMNS[item.column()][0]}")

    def _readouts(self) -> None:
        stations = self.sync.stations
        error = self.sync.errors.get("stations", "")
        self.error_label.setText(error if stations is None else "")
        if stations is None:
            self.images_label.setText("–")
            self.calc_label.setText("–")
            self.time_label.setText("–")
            return
        self.images_label.setText(f"{stations.n_images}")
        c = stations.calc
        if c is not None:
            # the field not chosen shows the value the chosen one implies (read-only)
            plan = self.project.trajectory.flight_plan
            derived_spin, value = ((self.gsd_spin, 100 * c.gsd_m)
                                   if plan is not None and plan.altitude_agl_m is not None
                                   else (self.altitude_spin, c.altitude_agl_m))
            if not derived_spin.isEnabled():
                derived_spin.blockSignals(True)
                derived_spin.setValue(value)
                derived_spin.blockSignals(False)
            ii = stations.interior
            scale = self.project.render.resolution_scale
            W, H = derived.rendered_size_px(ii, scale)
            rendered = (
                "" if scale == 1.0 else
                f"; rendered image ({W} × {H} px): GSD "
                f"{100 * derived.rendered_gsd_m(c.gsd_m, ii, scale):.2f} cm")
            self.calc_label.setText(
                f"{c.altitude_agl_m:.1f} m above ground; GSD {100 * c.gsd_m:.2f} cm for the "
                f"camera's {ii.image_width_px} × {ii.image_height_px} px{rendered}; "
                f"footprint {c.footprint_across_m:.1f} × {c.footprint_along_m:.1f} m; lines "
                f"{c.line_spacing_m:.1f} m apart, a photo every {c.trigger_distance_m:.1f} m")
        else:  # photos listed one by one (imported or written so): no grid to describe
            self.calc_label.setText(NO_GRID)
        if stations.render_costs:
            from designer.gui.state.render_figures import flight_estimate_line
            from designer.gui.state.wording import estimate_basis
            from designer.render_time.model import load_speed

            # this machine's speed as measured now (a render since may have refined it)
            self.time_label.setText(flight_estimate_line(
                derived.render_estimate(self.project, stations.render_costs),
                self.project.render.effective_samples,
                estimate_basis(load_speed(stations.render_costs[0]))))

    def _plan_readouts(self) -> None:
        """Figures of the flight over the real terrain and the warnings they raise; while
        they are computed (seconds at survey size) the box says so and the figures of
        before the edit, if any, are greyed."""
        f = self.sync.plan
        computing = self.sync.plan_computing
        self.real_box.setTitle(REAL_TITLE + (f" — {COMPUTING}" if computing else ""))
        for label in (self.real_gsd, self.real_overlap, self.real_images):
            label.setEnabled(not computing)
        if f is None:
            error = self.sync.errors.get("plan", "")
            for label in (self.real_gsd, self.real_images):
                label.setText("–")
            self.real_overlap.setText(COMPUTING if computing else
                                      f"not computed: {self._no_plan_reason(error)}")
            self._show_warnings()
            return
        scale = self.project.render.resolution_scale
        of = "" if scale == 1.0 else f" (rendered images, scale {scale:g})"
        self.real_gsd.setText(_gsd_text(f.gsd_min_m, f.gsd_max_m, f.gsd_median_m) + of)
        self.real_overlap.setText(_overlap_text(f))
        seen = ", ".join(f"{100 * v:.0f} % by ≥ {k}" for k, v in f.area_seen.items())
        # with a rig the figures are the stations' (their planning camera's), as designer
        # plan says: "of 37" next to 121 images would read as a fault
        of = (f"{f.n_images}" if f.n_rendered == f.n_images else
              f"{count(f.n_images, 'station')} (each station's planning camera)")
        self.real_images.setText(
            f"{f.images_over_area} of {of} look at the area, {f.images_over_terrain} "
            f"at the terrain; area seen {seen}")
        self._show_warnings()

    def _on_project(self, old, new, parts) -> None:
        super()._on_project(old, new, parts)
        # a moved building or area vertex may leave the ground; a lens or texel edit
        # changes the cases that degrade results
        self._show_warnings()

    def _show_warnings(self) -> None:
        """The places off the terrain file's ground, the cases that degrade results,
        then the plan's warnings (or why there is no plan)."""
        f = self.sync.plan
        lines = [f"⚠ {w}" for w in self.sync.reach_warnings() + self.sync.hard_case_warnings()]
        if f is not None:
            lines += [f"⚠ {w}" for w in f.warnings]
        elif self.sync.errors.get("plan"):
            lines.append(self.sync.errors["plan"])
        self.warnings_label.setText("\n".join(lines))
        self.warnings_label.setVisible(bool(lines))

    def _no_plan_reason(self, error: str) -> str:
        """Why the flight has no figures over the terrain, in words."""
        if error:
            return error
        if self.sync.stations is None:
            return self.sync.errors.get("stations") or "no flight to analyse"
        terrain = self.sync.terrain
        if terrain is not None and terrain.heightfield is None:
            return "the analysis needs a height-field terrain (a DEM or procedural)"
        return "the terrain is not ready yet"

    # ------------------------------------------------------------------ view → model
    def _mesh_reference_m(self) -> float | None:
        """A mesh terrain's mean height (a flight over it needs a given reference)."""
        terrain = self.sync.terrain
        if terrain is None or terrain.heightfield is not None:
            return None
        return terrain.z_mean_m

    def _given_reference_m(self) -> float:
        terrain = self.sync.terrain
        return round(terrain.z_mean_m, 3) if terrain is not None else 0.0

    def set_area(self, vertices) -> None:
        self._set_checked_draw(False)
        area = tuple((round(float(x), edits.COORDINATE_DECIMALS),
                      round(float(y), edits.COORDINATE_DECIMALS)) for x, y in vertices)
        self.editor.edit(edits.set_flight(self.project, area=area),
                         f"Flight area ({len(area)} vertices)")

    def _area_typed(self, _item) -> None:
        try:
            area = tuple((float(self.area_table.item(r, 0).text()),
                          float(self.area_table.item(r, 1).text()))
                         for r in range(self.area_table.rowCount()))
        except (ValueError, AttributeError):
            self.error_label.setText("area vertices must be numbers (m)")
            return
        self.editor.edit(edits.set_flight(self.project, area=area), "Flight area typed")

    def _height_mode(self, by_altitude: bool) -> None:
        plan = self.project.trajectory.flight_plan
        if plan is None or (plan.altitude_agl_m is not None) == by_altitude:
            return
        stations = self.sync.stations
        if by_altitude:
            altitude = stations.calc.altitude_agl_m if stations and stations.calc else 50.0
            new = edits.set_flight(self.project, altitude_agl_m=round(altitude, 2), gsd_m=None)
        else:
            gsd = stations.calc.gsd_m if stations and stations.calc else 0.02
            new = edits.set_flight(self.project, gsd_m=round(gsd, 5), altitude_agl_m=None)
        self.editor.edit(new, "Height above ground by " + ("altitude" if by_altitude else "GSD"))

    def _noise_toggled(self, on: bool) -> None:
        noise = m.PoseNoise(0.3, 0.3, 0.2, 0.5, 0.5, 1.0) if on else None
        self.editor.edit(edits.set_flight(self.project, pose_noise=noise),
                         "Pose noise " + ("on" if on else "off"))

    def _timing_toggled(self, on: bool) -> None:
        traj = self.project.trajectory
        if on == (traj.time_line is not None):
            return
        time_line = DEFAULT_TIME_LINE if on else None
        self.editor.edit(edits.replace_path(self.project, "trajectory.time_line", time_line),
                         "Time line " + ("on" if on else "off"))

    def _draw_toggled(self, on: bool) -> None:
        self.sync.view.interaction.set_mode("area" if on else "navigate")

    def _mode_changed(self, mode: str) -> None:
        self._set_checked_draw(mode == "area")

    def _set_checked_draw(self, on: bool) -> None:
        _check(self.draw, on)
        if not on and self.sync.view.interaction.mode == "area":
            self.sync.view.interaction.set_mode("navigate")


#: the time line a project gets when its photos are given times in the panel
DEFAULT_TIME_LINE = m.TimeLine("2026-06-21T09:30:00Z", speed_m_s=5.0, turn_s=8.0)


def _gsd_text(gsd_min_m: float, gsd_max_m: float, gsd_median_m: float) -> str:
    """The ground sample distance over the area, in words; figures that do not exist
    (no image sees the area, or none is centred over it) are said so, not shown as nan."""
    if not (np.isfinite(gsd_min_m) and np.isfinite(gsd_max_m)):
        return "– (no image sees the area)"
    text = f"{100 * gsd_min_m:.2f} to {100 * gsd_max_m:.2f} cm over the area, "
    if not np.isfinite(gsd_median_m):
        return text + "no image is centred over it"
    return text + f"median {100 * gsd_median_m:.2f} cm at the centres of the images over it"


def _overlap_text(f) -> str:
    """The achieved overlaps in words; one that cannot be measured is said so, with why
    (a template with dashes in place of the figures reads as a fault)."""
    def finite(v) -> bool:
        return v is not None and v == v

    if not f.images_over_area:
        return "not measured: no image looks at the area"
    if finite(f.front_overlap_median):
        front = (f"front {_pct(f.front_overlap_median)} (5 % of images below "
                 f"{_pct(f.front_overlap_p05)})")
    else:
        front = "front overlap not measured: no image over the area has a next one on its line"
    if finite(f.side_overlap_median):
        side = f"side {_pct(f.side_overlap_median)} (5 % below {_pct(f.side_overlap_p05)})"
    else:
        side = "side overlap not measured: a single flight line, no neighbouring line"
    return f"{front}; {side}" if not finite(f.front_overlap_median) or not finite(
        f.side_overlap_median) else f"{front}, {side}"


def _pct(v: float) -> str:
    return "–" if v is None or v != v else f"{100 * v:.0f} %"


def _check(button, on: bool) -> None:
    blocked = button.blockSignals(True)
    button.setChecked(on)
    button.blockSignals(blocked)


def _reference_kind(reference) -> str:
    return reference if isinstance(reference, str) else "given"


def _line() -> QLineEdit:
    return QLineEdit()
