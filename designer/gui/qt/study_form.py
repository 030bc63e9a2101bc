"""The study being edited in the Study panel: one row per factor (its levels typed as
values or a START:STOP:STEP range, the base project's value beside them), and the check
that runs off the UI thread — the study text parsed by the study reader, planned by
:func:`designer.study.design.plan_study` and costed by
:func:`designer.gui.state.study_data.plan_cost`."""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import Signal
from PySide6.QtWidgets import QHBoxLayout, QLabel, QLineEdit, QToolButton, QWidget

from designer.gui.state.study_data import parse_levels, parse_range
from designer.gui.state.study_words import factor_words, tip

LEVELS_HINT = "values separated by spaces (3 4 6 8), or a range START:STOP:STEP (20:40:5)"


class FactorRow(QWidget):
    """A factor of the study: its name, its levels, a button that removes it."""

    changed = Signal()
    remove = Signal(object)

    def __init__(self, name: str, stage: str, doc: str, base_value: str,
                 levels: str = "", parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.name = name
        self.words = factor_words(name)
        row = QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        self.stage = stage
        self.label = QLabel()
        self.label.setToolTip(tip(f"{doc}\nIts value in the base project is the base "
                                  "level: one at a time, the base run keeps it and every "
                                  "other run changes this factor alone", name))
        self.label.setMinimumWidth(150)
        self.set_base(base_value)
        label = self.label
        self.levels = QLineEdit(levels)
        self.levels.setObjectName(f"levels-{name}")
        self.levels.setPlaceholderText("levels, e.g. 3 4 6 or 20:40:5")
        self.levels.setToolTip(f"{doc}\nLevels: {LEVELS_HINT}")
        self.levels.textChanged.connect(lambda _t: self.changed.emit())
        self.count = QLabel("")
        self.count.setMinimumWidth(56)
        self.remove_button = QToolButton()
        self.remove_button.setObjectName(f"remove-{name}")
        self.remove_button.setText("✕")
        self.remove_button.setToolTip(f"remove the factor “{self.words}”")
        self.remove_button.clicked.connect(lambda: self.remove.emit(self))
        row.addWidget(label)
        row.addWidget(self.levels, 1)
        row.addWidget(self.count)
        row.addWidget(self.remove_button)

    def set_base(self, base_value: str) -> None:
        """Show the factor's value in the study's base project ("" when it sets none)."""
        self.base_value = base_value
        self.label.setText(f"<b>{self.words}</b><br><small>{self.stage}; in the base "
                           f"project: {base_value or 'not set'}</small>")

    def values(self) -> tuple[str, ...]:
        """The levels; ValueError names the factor and what is wrong."""
        try:
            values = parse_levels(self.levels.text())
        except ValueError as error:
            self.count.setText("")
            raise ValueError(f"factor “{self.words}”: {error}") from None
        self.count.setText(f"{len(values)} level{'s' if len(values) != 1 else ''}")
        return values

    def range_spec(self) -> tuple[float, float, float] | None:
        """(start, stop, step) when the levels are typed as a range, else None."""
        return parse_range(self.levels.text())


_terrain_cache: dict[str, object] = {}


def _heightfield(plan):
    """The base project's heightfield (the last one kept: edits of the study reuse it)."""
    from designer.gui.state import derived

    key = repr((plan.base.scene.terrain, str(plan.base_dir)))
    if key not in _terrain_cache:
        _terrain_cache.clear()
        _terrain_cache[key] = derived.compute_terrain(plan.base, plan.base_dir).heightfield
    return _terrain_cache[key]


class OpenProjectInvalid(Exception):
    """The study's base is the window's project with unsaved changes (or never saved),
    and it is not valid: its problems at the lines of the project as it would be saved."""

    def __init__(self, error) -> None:
        from designer.gui.state.wording import problem_text

        super().__init__(str(error))
        # worded as the Problems list words them (the panel and control that fix each)
        problems = getattr(error, "problems", None)
        lines = ([problem_text(p, error.source) for p in problems] if problems
                 else list(error.lines))
        self.lines = ["the study's base is the open project with unsaved changes, and they "
                      "are not valid (lines of the project file as it would be saved; "
                      "Problems lists them too):", *lines]


def check_open_project(project, source: str, base_dir: Path) -> None:
    """The window's project checked as Save would write it, named ``source`` (its file);
    :class:`OpenProjectInvalid` when it is not valid."""
    from designer.project import parse_project, project_to_bytes, semantic_problems
    from designer.project.problems import ProjectError

    try:
        parsed, smap = parse_project(project_to_bytes(project), source)
    except ProjectError as error:
        raise OpenProjectInvalid(error) from None
    problems = semantic_problems(parsed, base_dir, smap)
    if problems:
        raise OpenProjectInvalid(ProjectError(source, problems))


def design_text(plan) -> str:
    """What the design makes of the base project, in words: one at a time, the base
    project as it is (each factor's value in it) and one variant per level; full
    factorial, every combination."""
    if plan.study.design != "one-at-a-time":
        return ("full factorial: every combination of the levels; the rest as in the base "
                "project")
    from designer.study.factors import FACTORS

    values = []
    for f in plan.study.factors:
        value = base_value(FACTORS[f.name], plan.base)
        words = factor_words(f.name)
        values.append(f"{words} {value}" if value else f"{words} not set in it")
    n = plan.n_variants - 1
    return (f"one at a time: the base project as it is ({', '.join(values)}) and {n} "
            f"variant{'s' if n != 1 else ''}, each one factor at one of its levels")


def base_value(factor, project) -> str:
    """``factor``'s value in ``project`` as text ("" when the project sets none)."""
    from designer.study.design import _text

    try:
        return _text(factor.get(project))
    except (ValueError, AttributeError, KeyError, IndexError):
        return ""


def check_study(text: str | None, source: str, path: Path, speed=None, open_project=None):
    """(plan, cost) of the study ``text`` (None: the file ``path`` as it is on disk), the
    cost with the warnings of runs that would fail; ProjectError lines
    ``FILE:LINE:COL: <element>: message`` for anything wrong. ``open_project``: (project,
    its file's name, its folder) when the study's base is the window's project written
    into the study (unsaved changes): its problems are told at its own lines first."""
    from dataclasses import replace

    from designer.gui.state.study_data import plan_cost, plan_warnings
    from designer.study.design import plan_study
    from designer.study.xml import parse_study, read_study

    if open_project is not None:
        check_open_project(*open_project)
    study = read_study(path) if text is None else parse_study(text.encode(), source, path)
    plan = plan_study(study)
    cost = plan_cost(plan, _heightfield(plan), speed)
    return plan, replace(cost, warnings=tuple(plan_warnings(plan)))
