"""Processing: how ``designer reconstruct`` treats the rendered images (the project's
``<processing>``) — which interior parameters the adjustment estimates and how wrong
the starting calibration is, how the GCPs enter and how precisely they are marked, the
camera positions measured in flight, matching, and the dense cloud.

Without ``<processing>`` the reconstruction uses its defaults; the check box at the top
adds the element with those defaults (one undo step) or removes it.
"""

from __future__ import annotations

import dataclasses

from PySide6.QtWidgets import QCheckBox, QGroupBox, QLabel, QLineEdit

from designer.gui.qt.field_rules import ruled_ispin
from designer.gui.qt.panels.base import Panel
from designer.gui.qt.widgets import (
    INVALID_STYLE,
    combo,
    declared_field,
    dspin,
    form,
    ispin,
    model_getter,
    readout,
)
from designer.gui.state import edits
from designer.project import model as m
from designer.project.processing import POSITION_PRIOR_SIGMAS_M
from designer.project.validate_processing import MIN_SIMILARITY_CONTROL

P = "processing"
CAL, PRE, GCP, CTL, PRIOR, MATCH = (f"{P}.calibration", f"{P}.calibration.pre_calibration_error",
                                    f"{P}.gcps", f"{P}.gcps.control", f"{P}.position_prior",
                                    f"{P}.matching")
CALIBRATIONS = [("fixed (the camera as given)", "fixed"), ("focal length", "focal"),
                ("focal length and principal point", "focal-principal-point"),
                ("focal, principal point, k1, k2 (radial)", "radial"),
                ("full (focal, principal point, k1–k3, p1, p2)", "full")]
GCP_MODES = [("not used", "none"), ("similarity after SfM (7 parameters)", "similarity"),
             ("in the bundle adjustment", "bundle")]
PRIORS = [("not used", "none"), ("GNSS (consumer drone)", "gnss"), ("RTK / PPK", "rtk")]
PAIRS = [("by ground footprint", "footprint"), ("by camera position", "position"),
         ("every pair (exhaustive)", "exhaustive")]
ROLLING = [("as global-shutter images", "none"),
           ("compensated: each image's velocity in the adjustment", "compensate")]
SIFT_SCALES = [("doubled (COLMAP's default)", "doubled"),
               ("original (a quarter of the work)", "original"), ("half", "half")]
DENSE = [("off (sparse cloud only)", "none"),
         ("CPU (semi-global matching + fusion)", "cpu"), ("automatic", "auto")]


def _seed() -> object:
    return ispin(0, 2**31 - 1)


def _sigma_or_default(default_text: str):
    box = dspin(0, 1000, 3, 0.01, "m")
    box.setSpecialValueText(default_text)
    return box


def _parse_ids(text: str) -> tuple[str, ...]:
    return tuple(i.strip() for i in text.replace(";", ",").split(",") if i.strip())


def _set_ids(project: m.Project, text: str) -> m.Project:
    ids = _parse_ids(text)
    control = project.processing.gcps.control
    return edits.replace_path(project, CTL, dataclasses.replace(
        control, ids=ids, count=None if ids else (control.count or len(project.targets))))


def _set_count(project: m.Project, count: int) -> m.Project:
    control = project.processing.gcps.control
    return edits.replace_path(project, CTL, dataclasses.replace(
        control, count=count or None, ids=() if count else control.ids))


class ProcessingPanel(Panel):
    title = "Processing"
    parts = frozenset({"processing", "targets", "cameras"})

    def build(self, layout) -> None:
        b = self.bindings
        self.enabled = QCheckBox("the project's own processing settings")
        self.enabled.setToolTip("without them designer reconstruct uses its defaults")
        self.enabled.toggled.connect(self._toggle_processing)
        layout.addWidget(self.enabled)

        cal = QGroupBox("camera calibration")
        f = form(cal)
        f.addRow("estimated", b.bind(combo(CALIBRATIONS), f"{CAL}.mode", "Calibration"))
        self.pre = QCheckBox("start from a wrong calibration (σ of its errors)")
        self.pre.toggled.connect(lambda on: self._toggle(
            PRE, m.PreCalibrationError(focal_px=5.0, principal_point_px=2.0) if on else None,
            "pre-calibration error"))
        f.addRow(self.pre)
        for label, name in (("focal length", "focal_px"),
                            ("principal point", "principal_point_px"), ("k1", "k1"),
                            ("k2", "k2"), ("k3", "k3"), ("p1", "p1"), ("p2", "p2"),
                            ("seed", "seed")):
            f.addRow(f"σ {label}" if name != "seed" else label,
                     b.bind(declared_field(m.PreCalibrationError, name), f"{PRE}.{name}",
                            f"Pre-calibration error {label}"))
        f.addRow("rolling shutter", b.bind(combo(ROLLING), f"{CAL}.rolling_shutter",
                                           "Rolling-shutter processing"))
        self.rolling_note = QLabel()
        self.rolling_note.setWordWrap(True)
        self.rolling_note.setStyleSheet("color: #b36b00;")
        f.addRow(self.rolling_note)
        layout.addWidget(cal)

        gcp = QGroupBox("ground control")
        f = form(gcp)
        self.mode = b.bind(combo(GCP_MODES), (model_getter(f"{GCP}.mode"), self._checked_mode),
                           "GCP use")
        self.mode.setObjectName(f"{GCP}.mode")  # found by its path, as the other fields
        f.addRow("GCPs", self.mode)
        f.addRow("marking error σ", b.bind(declared_field(m.GcpProcessing, "marking_sigma_px"),
                                           f"{GCP}.marking_sigma_px", "GCP marking error σ"))
        f.addRow("seed", b.bind(_seed(), f"{GCP}.seed", "GCP marking seed"))
        self.subset = QCheckBox("a subset of the targets as control, the rest check")
        self.subset.toggled.connect(lambda on: self._toggle(
            CTL, m.ControlSelection(count=max(3, len(self.project.targets) // 2)) if on
            else None, "control selection"))
        f.addRow(self.subset)
        self.ids = ids = QLineEdit()
        ids.setPlaceholderText("GCP01, GCP04, …")
        f.addRow("by id", b.bind(ids, (model_getter(f"{CTL}.ids", ", ".join),
                                       self._checked_ids), "Control ids"))
        count = ruled_ispin(self._count_problem, 0, 10000)
        count.setSpecialValueText("by id")
        f.addRow("or a count", b.bind(count, (model_getter(
            f"{CTL}.count", lambda v: 0 if v is None else v), _set_count), "Control count"))
        f.addRow("spread", b.bind(combo([("evenly", "even"), ("at random", "random")]),
                                  f"{CTL}.spread", "Control spread"))
        f.addRow("seed", b.bind(_seed(), f"{CTL}.seed", "Control seed"))
        layout.addWidget(gcp)

        prior = QGroupBox("camera positions measured in flight")
        f = form(prior)
        f.addRow("prior", b.bind(combo(PRIORS), f"{PRIOR}.mode", "Position prior"))
        self.prior_fields = []
        for label, name in (("σ horizontal", "sigma_horizontal_m"),
                            ("σ vertical", "sigma_vertical_m")):
            self.prior_fields.append(b.bind(_sigma_or_default("the mode's default"), (
                model_getter(f"{PRIOR}.{name}", lambda v: 0.0 if v is None else v),
                lambda p, v, n=name: edits.replace_path(p, f"{PRIOR}.{n}", v or None)),
                f"Position prior {label}"))
            f.addRow(label, self.prior_fields[-1])
        self.prior_sigmas = readout()
        f.addRow("in use", self.prior_sigmas)
        self.prior_fields.append(b.bind(_seed(), f"{PRIOR}.seed", "Position prior seed"))
        f.addRow("seed", self.prior_fields[-1])
        layout.addWidget(prior)

        match = QGroupBox("matching")
        f = form(match)
        f.addRow("SIFT features", b.bind(ispin(100, 1_000_000, "per image"),
                                         f"{MATCH}.max_features", "SIFT features"))
        f.addRow("SIFT image size", b.bind(combo(SIFT_SCALES), f"{MATCH}.sift_scale",
                                             "SIFT image size"))
        f.addRow("pairs", b.bind(combo(PAIRS), f"{MATCH}.pairs", "Matched pairs"))
        f.addRow("tie points in", b.bind(ispin(2, 100, "images or more"),
                                         f"{MATCH}.min_track_length", "Minimum track length"))
        layout.addWidget(match)

        dense = QGroupBox("dense cloud")
        f = form(dense)
        f.addRow("dense matching", b.bind(combo(DENSE), f"{P}.dense", "Dense matching"))
        note = QLabel("on: the reconstruction also writes dense.ply, a DSM and the DEM of "
                      "difference against the true terrain (Results panel)")
        note.setWordWrap(True)
        f.addRow(note)
        layout.addWidget(dense)
        self.groups = (cal, gcp, prior, match, dense)

    def refresh(self) -> None:
        p = self.project.processing
        # without <processing> the greyed fields show what designer reconstruct then uses
        # (its defaults), not whatever the fields held last
        self.bindings.refresh(self.project if p is not None else dataclasses.replace(
            self.project, processing=m.Processing()))
        self._show_ids_verdict("")  # the field shows the project's ids again
        self._field_verdict(self.mode, "")
        for box, on in ((self.enabled, p is not None),
                        (self.pre, p is not None and p.calibration.pre_calibration_error
                         is not None),
                        (self.subset, p is not None and p.gcps.control is not None)):
            blocked = box.blockSignals(True)
            box.setChecked(on)
            box.blockSignals(blocked)
        for group in self.groups:
            group.setEnabled(p is not None)
        rolling = any(c.readout_s > 0 for c in self.project.cameras)
        self.rolling_note.setText(
            "" if p is None or p.calibration.rolling_shutter != "compensate" or rolling else
            "no camera of the project has a rolling shutter, so there is nothing to "
            "compensate (the reconstruction refuses it): give the camera a rolling-shutter "
            "readout in the Camera panel, or process the images as global-shutter ones")
        # the prior's σ and seed mean nothing while no positions are measured
        for box in self.prior_fields:
            box.setEnabled(p is not None and p.position_prior.mode != "none")
        if p is None or p.position_prior.mode == "none":
            self.prior_sigmas.setText("–")
        else:
            h, v = p.position_prior.sigmas_m
            dh, dv = POSITION_PRIOR_SIGMAS_M[p.position_prior.mode]
            self.prior_sigmas.setText(f"{h:g} m horizontal, {v:g} m vertical (the mode's "
                                      f"default: {dh:g} m, {dv:g} m)")

    def _control_problem(self, n: int, verb: str) -> str:
        """Why ``n`` control GCPs are too few for the GCP mode ("" when they are not)."""
        p = self.project.processing
        if p is not None and p.gcps.mode == "similarity" and 0 < n < MIN_SIMILARITY_CONTROL:
            return (f"a similarity after SfM needs at least {MIN_SIMILARITY_CONTROL}; {verb} "
                    "more or let the GCPs enter in the bundle adjustment")
        return ""

    def _count_problem(self, count: float) -> str:
        n, total = int(count), len(self.project.targets)
        if n > total:
            return (f"control count {n} is more than the project's {total} GCPs; choose "
                    f"1 to {total}" if total else
                    f"control count {n}: the project has no GCPs; add them in the GCPs panel "
                    "first")
        reason = self._control_problem(n, "choose")
        return f"control count {n}, but {reason}" if reason else ""

    def _ids_problem(self, ids: tuple[str, ...]) -> str:
        known = [t.id for t in self.project.targets]
        unknown = [i for i in ids if i not in known]
        if unknown:
            have = ", ".join(known[:2] + ["…"] + known[-1:] if len(known) > 4 else known)
            return (f"control GCPs: {unknown[0]} is not a GCP of the project "
                    f"({have or 'it has none'})")
        twice = [i for i in dict.fromkeys(ids) if ids.count(i) > 1]
        if twice:
            return f"control GCPs: {twice[0]} is listed twice; list each once"
        reason = self._control_problem(len(ids), "name")
        return f"control GCPs: {len(ids)} GCPs, but {reason}" if reason else ""

    def _checked_mode(self, project: m.Project, mode: str) -> m.Project:
        """The project with GCP mode ``mode``, or unchanged (the choice put back, saying
        why) when it is a similarity and the control selection has too few GCPs."""
        gcps = project.processing.gcps
        control = gcps.control
        n = len(set(control.ids)) if control is not None and control.ids else (
            control.count or 0 if control is not None else 0)
        if mode != "similarity" or not 0 < n < MIN_SIMILARITY_CONTROL:
            self._field_verdict(self.mode, "")
            return edits.replace_path(project, f"{GCP}.mode", mode)
        what = (f"control GCPs ({', '.join(control.ids)})" if control.ids else
                f"control count {control.count}")
        self._field_verdict(self.mode, (
            f"GCP use: a similarity after SfM needs at least {MIN_SIMILARITY_CONTROL} control "
            f"GCPs, and {what} gives {n}; name more below, or keep the GCPs in the bundle "
            "adjustment; not applied"))
        blocked = self.mode.blockSignals(True)
        self.mode.setCurrentIndex(self.mode.findData(gcps.mode))
        self.mode.blockSignals(blocked)
        return project

    def _checked_ids(self, project: m.Project, text: str) -> m.Project:
        """The project with control ids ``text``, or unchanged (the field red, saying
        why) when they name no GCP or too few for the GCP mode."""
        reason = self._ids_problem(_parse_ids(text))
        self._show_ids_verdict(f"{reason}; not applied" if reason else "")
        return project if reason else _set_ids(project, text)

    def _show_ids_verdict(self, message: str) -> None:
        self.ids.setProperty("invalid", bool(message))
        self.ids.setStyleSheet(INVALID_STYLE if message else "")
        self.ids.setToolTip(message)
        self._field_verdict(self.ids, message)

    def _toggle_processing(self, on: bool) -> None:
        self.editor.edit(dataclasses.replace(
            self.project, processing=m.Processing() if on else None),
            "processing settings " + ("added" if on else "removed"))

    def _toggle(self, path: str, value, what: str) -> None:
        self.editor.edit(edits.replace_path(self.project, path, value),
                         f"{what} {'on' if value is not None else 'off'}")
