"""GCPs: the target table (true and surveyed coordinates, roles), placing by clicking on
the terrain, dragging, deleting, automatic layouts and the simulated survey's σ."""

from __future__ import annotations

import dataclasses

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor, QKeySequence, QShortcut
from PySide6.QtWidgets import (
    QAbstractItemView,
    QCheckBox,
    QComboBox,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from designer.errors import DesignerError
from designer.gui.qt.panels.base import Panel
from designer.gui.qt.widgets import MessageLabel, combo, dspin, form, format_number, ispin
from designer.gui.state import edits, wording
from designer.project import model as m

COLUMNS = ["id", "role", "X", "Y", "Z", "size m", "surveyed X", "surveyed Y", "surveyed Z",
           "images"]
#: the headers' tooltips
COLUMN_TIPS = {"Z": "the target's true height; blank: on the ground",
               "surveyed X": "blank: the simulated survey (σ below) gives it",
               "images": "images of the flight that see the GCP unoccluded (red below 3)"}
#: the read-only column: images of the flight that see the GCP (over the real terrain)
IMAGES_COLUMN = 9
#: the true Z, kept as wide as Z_WIDEST (a height with its millimetres) and the cell's
#: padding (px)
Z_COLUMN = 4
Z_WIDEST = "8888.888"
CELL_PADDING_PX = 12
#: the height of the table with its messages under it (px)
TABLE_BOX_PX = 280


#: background of a cell whose typed text was refused
INVALID_CELL = "#f4b6b0"


def _number(text: str, blank_ok: bool = False) -> float | None:
    """A typed number (m); a message the user can act on when it is not one."""
    raw = text.strip().replace(",", ".")
    if raw == "":
        if blank_ok:
            return None
        raise ValueError("give a number (m)")
    try:
        value = float(raw)
    except ValueError:
        raise ValueError(f"“{text.strip()}” is not a number (m)") from None
    if value != value or abs(value) == float("inf"):
        raise ValueError(f"“{text.strip()}” is not a finite number (m)")
    return value


class GcpPanel(Panel):
    title = "GCPs"
    parts = frozenset({"targets", "terrain"})

    def build(self, layout) -> None:
        self._cell_errors: dict[tuple[str, int], str] = {}
        row = QHBoxLayout()
        self.place = QPushButton("Place by clicking")
        self.place.setCheckable(True)
        self.place.setToolTip("Click on the terrain to add a GCP; drag a GCP to move it")
        self.place.toggled.connect(self._place_toggled)
        self.delete_button = QPushButton("Delete")
        self.delete_button.clicked.connect(self.delete_selected)
        row.addWidget(self.place)
        row.addWidget(self.delete_button)
        layout.addLayout(row)

        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        for c, name in enumerate(COLUMNS):
            tip = COLUMN_TIPS.get(name, COLUMN_TIPS["surveyed X"] if "surveyed" in name
                                  else "")
            self.table.horizontalHeaderItem(c).setToolTip(tip)
        header = self.table.horizontalHeader()
        # the images each GCP is seen in beside its role: id, role, images and the true
        # position show without scrolling; the survey's columns follow
        header.moveSection(IMAGES_COLUMN, 2)
        self.table.verticalHeader().hide()  # the id names the row
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setMinimumHeight(120)
        self.table.itemChanged.connect(self._cell_edited)
        QShortcut(QKeySequence.StandardKey.Delete, self.table, self.delete_selected)
        # the table's messages under it, in a box of fixed height: a message (or a
        # longer one) shortens the table and does not push the fields below down
        self.error_label = MessageLabel()
        table_box = QWidget()
        v = QVBoxLayout(table_box)
        v.setContentsMargins(0, 0, 0, 0)
        v.addWidget(self.table, 1)
        v.addWidget(self.error_label)
        table_box.setFixedHeight(TABLE_BOX_PX)
        layout.addWidget(table_box)

        auto = QGroupBox("automatic layout (replaces the targets)")
        f = form(auto)
        self.layout_kind = combo([("grid", "grid"), ("random, stratified", "random"),
                                  ("perimeter and centre", "perimeter")])
        self.count = ispin(1, 1000)
        self.count.setValue(9)
        self.n_check = ispin(0, 1000)
        self.n_check.setValue(3)
        self.margin = dspin(0, 1e5, 2, 1, "m")
        self.margin.setValue(10)
        self.spacing = dspin(0, 1e5, 2, 1, "m")
        self.spacing.setValue(15)
        self.layout_seed = ispin(0, 2**31 - 1)
        self.size = dspin(0.05, 10, 3, 0.1, "m")
        self.size.setValue(0.8)
        apply = QPushButton("Apply layout")
        apply.clicked.connect(self.apply_layout)
        for label, widget in (("layout", self.layout_kind), ("GCPs", self.count),
                              ("of which check points", self.n_check),
                              ("margin", self.margin), ("min spacing (random)", self.spacing),
                              ("seed", self.layout_seed), ("target size", self.size),
                              ("", apply)):
            f.addRow(label, widget)
        layout.addWidget(auto)

        survey = QGroupBox("simulated survey of the targets")
        f = form(survey)
        # a short check box text and the rest wrapped below it: a check box does not
        # wrap, and a long one would make the panel wider than its dock (cutting the
        # messages at its right edge)
        self.simulate = QCheckBox("add survey error")
        self.simulate.toggled.connect(self._simulate_toggled)
        f.addRow(self.simulate)
        which = QLabel("to the targets without measured positions")
        which.setWordWrap(True)
        f.addRow(which)
        acc = "scene.targets.survey_accuracy"
        for axis in "XYZ":
            f.addRow(f"σ {axis}", self.bindings.bind(dspin(0, 10, 4, 0.005, "m"),
                                                     f"{acc}.sigma.{axis}", f"Survey σ {axis}"))
        f.addRow("seed", self.bindings.bind(ispin(0, 2**31 - 1), f"{acc}.seed", "Survey seed"))
        layout.addWidget(survey)

        view = self.sync.view
        view.ground_clicked.connect(self.add_at)
        view.target_moved.connect(self.move_target)
        view.interaction.mode_changed.connect(
            lambda mode: self._set_checked(self.place, mode == "place"))
        self.sync.targets_changed.connect(self.refresh)
        self.sync.plan_changed.connect(self._image_counts)

    @staticmethod
    def _set_checked(button, checked: bool) -> None:
        blocked = button.blockSignals(True)
        button.setChecked(checked)
        button.blockSignals(blocked)

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        super().refresh()
        project = self.project
        self._set_checked(self.simulate, project.scene.targets is not None
                          and project.scene.targets.survey_accuracy is not None)
        built = self.sync.targets
        true_z = {}
        if built is not None and self.sync.terrain is not None:
            for k, tid in enumerate(built.ids):
                true_z[tid] = built.true_xyz[k, 2]
        self.table.blockSignals(True)
        try:
            self.table.setRowCount(len(project.targets))
            for r, t in enumerate(project.targets):
                z = t.true.Z
                for c, text in enumerate(_cells(t)):
                    if c == 1:
                        self._role_box(r, t.role)
                        continue
                    item = QTableWidgetItem(text)
                    if c == 4 and z is None and t.id in true_z:
                        item.setToolTip(f"on the ground: Z = {true_z[t.id]:.3f} m")
                        item.setData(Qt.ItemDataRole.UserRole, float(true_z[t.id]))
                    if c >= 6 and t.surveyed is None:
                        item.setToolTip("blank: the simulated survey (σ below) gives it")
                    self.table.setItem(r, c, item)
        finally:
            self.table.blockSignals(False)
        self._image_counts()
        # as narrow as their numbers and headers: the columns a surveyor reads at once fit
        self.table.resizeColumnsToContents()
        # the true Z as wide as a height even while every GCP lies on the ground (blank):
        # typing one does not push the column past the dock's edge
        z_px = self.table.fontMetrics().horizontalAdvance(Z_WIDEST) + CELL_PADDING_PX
        self.table.setColumnWidth(Z_COLUMN, max(self.table.columnWidth(Z_COLUMN), z_px))
        self._cell_errors.clear()  # the table shows the project's values again
        self._show_cell_errors()
        if built is None and project.targets and "targets" in self.sync.errors:
            self.error_label.setText("\n".join(
                [*self._cell_errors.values(), self.sync.errors["targets"]]))

    def _image_counts(self) -> None:
        """The images column: how many images of the flight see each GCP."""
        from designer.gui.state.plan_figures import MIN_GCP_IMAGES

        plan = self.sync.plan
        counts = dict(zip(plan.gcp_ids, plan.gcp_images, strict=True)) if plan else {}
        self.table.blockSignals(True)
        try:
            for r, t in enumerate(self.project.targets):
                n = counts.get(t.id)
                item = QTableWidgetItem("–" if n is None else str(int(n)))
                item.setFlags(item.flags() & ~Qt.ItemFlag.ItemIsEditable)
                if n is not None and n < MIN_GCP_IMAGES:
                    item.setBackground(QColor(INVALID_CELL))
                    item.setToolTip(f"seen by fewer than {MIN_GCP_IMAGES} images")
                self.table.setItem(r, IMAGES_COLUMN, item)
        finally:
            self.table.blockSignals(False)

    def _role_box(self, row: int, role: str) -> None:
        box = QComboBox()
        box.setFocusPolicy(Qt.FocusPolicy.StrongFocus)  # the wheel alone must not flip it
        box.addItems(["control", "check"])
        box.setCurrentText(role)
        box.currentTextChanged.connect(lambda text, r=row: self._set_role(r, text))
        self.table.setCellWidget(row, 1, box)

    # ------------------------------------------------------------------ view → model
    def _place_toggled(self, on: bool) -> None:
        self.sync.view.interaction.set_mode("place" if on else "navigate")

    def add_at(self, X: float, Y: float, Z: float) -> None:
        project = self.project
        new = edits.add_target(project, X, Y)
        tid = new.targets[-1].id
        self.editor.edit(new, f"Place {tid} at {X:.2f}, {Y:.2f}")

    def move_target(self, target_id: str, X: float, Y: float) -> None:
        self.editor.edit(edits.move_target(self.project, target_id, X, Y),
                         f"Move {target_id}")

    def delete_selected(self) -> None:
        rows = sorted({i.row() for i in self.table.selectedIndexes()})
        ids = [self.project.targets[r].id for r in rows if r < len(self.project.targets)]
        if not ids:
            return
        problem = edits.deletion_problem(self.project, ids)
        if problem:
            self.error_label.setText(problem)
            return
        self.editor.edit(edits.delete_targets(self.project, ids), f"Delete {', '.join(ids)}")

    def _set_role(self, row: int, role: str) -> None:
        t = self.project.targets[row]
        self.editor.edit(edits.replace_target(self.project, row,
                                              dataclasses.replace(t, role=role)),
                         f"{t.id} role {role}")

    def _cell_edited(self, item: QTableWidgetItem) -> None:
        """A typed cell is applied when valid; else it turns red, keeps the text and the
        panel says what it accepts (nothing reaches the project)."""
        r, c = item.row(), item.column()
        t = self.project.targets[r]
        text = item.text()
        name = f"{t.id} {COLUMNS[c].split(' (')[0]}"
        try:
            if c == 0:
                new_id = text.strip()
                problem = edits.identifier_problem(new_id)
                if problem:
                    raise ValueError(problem)
                others = [k for k, o in enumerate(self.project.targets)
                          if k != r and o.id == new_id]
                if others:
                    raise ValueError(f"“{new_id}” is the id of another GCP (row "
                                     f"{others[0] + 1})")
                new = dataclasses.replace(t, id=new_id)
            elif c in (2, 3, 4):
                field = "XYZ"[c - 2]
                value = _number(text, blank_ok=field == "Z")
                if value is not None:
                    value = round(value, edits.COORDINATE_DECIMALS)
                new = dataclasses.replace(t, true=dataclasses.replace(t.true, **{field: value}))
            elif c == 5:
                value = _number(text)
                if not 0.01 <= value <= 100:
                    raise ValueError(f"{wording.fixed(value)} is out of range; allowed: "
                                     "0.01 to 100 m")
                new = dataclasses.replace(t, size_m=value)
            elif c == IMAGES_COLUMN:
                return
            else:
                new = self._surveyed(t, r)
        except ValueError as error:
            self._cell_errors[(t.id, c)] = f"{name}: {error}; not applied"
            self.table.blockSignals(True)
            item.setBackground(QColor(INVALID_CELL))
            item.setToolTip(str(error))
            self.table.blockSignals(False)
            self._show_cell_errors()
            return
        self._cell_errors.pop((t.id, c), None)
        if c >= 6:
            for k in (6, 7, 8):
                self._cell_errors.pop((t.id, k), None)
        self._show_cell_errors()
        project = edits.replace_target(self.project, r, new)
        if project == self.project:
            # the project's value typed again (after a refusal, or as "511962"): no edit,
            # and the cell shows it as the others are shown, no longer red
            self.table.blockSignals(True)
            item.setText(_cells(t)[c])
            item.setData(Qt.ItemDataRole.BackgroundRole, None)
            item.setToolTip("")
            self.table.blockSignals(False)
            return
        if new.id != t.id:  # the control selection follows a renamed GCP
            project = edits.rename_target_references(project, t.id, new.id)
        self.editor.edit(project, f"Edit {t.id}")

    def _show_cell_errors(self) -> None:
        ids = {t.id for t in self.project.targets}
        for key in [k for k in self._cell_errors if k[0] not in ids]:
            self._cell_errors.pop(key)
        lines = list(self._cell_errors.values())
        self.error_label.setText("\n".join(lines))

    def _surveyed(self, t: m.Target, row: int) -> m.Target:
        values = [_number(self.table.item(row, c).text() if self.table.item(row, c) else "",
                          blank_ok=True) for c in (6, 7, 8)]
        values = [None if v is None else round(v, edits.COORDINATE_DECIMALS) for v in values]
        if all(v is None for v in values):
            return dataclasses.replace(t, surveyed=None)
        if any(v is None for v in values):
            raise ValueError("give all three surveyed coordinates, or none")
        acc = self.project.scene.targets.survey_accuracy if self.project.scene.targets else None
        sigma = acc.sigma if acc is not None else m.Sigma3(0.01, 0.01, 0.02)
        return dataclasses.replace(t, surveyed=m.SurveyedPosition(m.Point3(*values), sigma))

    def _simulate_toggled(self, on: bool) -> None:
        accuracy = m.SurveyAccuracy(m.Sigma3(0.01, 0.01, 0.02), seed=0) if on else None
        self.editor.edit(edits.set_targets(self.project, self.project.targets, accuracy),
                         "Simulated survey " + ("on" if on else "off"))

    def apply_layout(self) -> None:
        from designer.survey import area as survey_area
        from designer.survey import gcp_layout

        project = self.project
        plan = project.trajectory.flight_plan
        area = np.array(plan.area if plan is not None and len(plan.area) >= 3
                        else edits.terrain_rectangle(project))
        n, kind = self.count.value(), self.layout_kind.currentData()
        if self.n_check.value() > n:
            # checked here, in the numbers typed: the layout would quietly make every
            # GCP a check point and leave none for control
            self.error_label.setText(
                f"of which check points: {wording.count(self.n_check.value(), 'check point')}"
                f" of {wording.count(n, 'GCP')}; give at most {n}; not applied")
            return
        # each step's failure is named from the field it came from, in the number typed
        step = f"margin {format_number(self.margin.value(), 2)} m"
        try:
            if kind == "grid":
                nx = int(np.ceil(np.sqrt(n)))
                xy = gcp_layout.grid(nx, int(np.ceil(n / nx)), area, self.margin.value())[:n]
            elif kind == "random":
                inner = survey_area.inset(area, self.margin.value())
                step = f"min spacing (random) {format_number(self.spacing.value(), 2)} m"
                xy = gcp_layout.random_stratified(n, inner, self.spacing.value(),
                                                  self.layout_seed.value())
            else:
                xy = gcp_layout.perimeter_and_centre(n, area, self.margin.value())
            step = f"GCPs {n}"
            roles = gcp_layout.assign_roles(len(xy), self.n_check.value(),
                                            pattern="interleaved")
        except DesignerError as error:
            self.error_label.setText(f"{step}: {wording.error_text(error)}; not applied")
            return
        new = edits.layout_targets(project, xy, roles, self.size.value())
        problem = edits.control_problem(project, new, "layout not applied")
        self.error_label.setText(problem)
        if not problem:
            self.editor.edit(new, f"GCP layout: {len(xy)} by {kind}")


def _cells(t: m.Target) -> list[str | None]:
    """A GCP's row as the table shows it (the role, a drop-down list, is None)."""
    z = t.true.Z
    cells = [t.id, None, f"{t.true.X:.3f}", f"{t.true.Y:.3f}",
             "" if z is None else f"{z:.3f}", f"{t.size_m:g}"]
    if t.surveyed is not None:
        p = t.surveyed.position
        return cells + [f"{p.X:.3f}", f"{p.Y:.3f}", f"{p.Z:.3f}"]
    return cells + ["", "", ""]
