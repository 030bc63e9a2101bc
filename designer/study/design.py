"""From a study to its runs: the base project, the variants of the design, the replicates.

Everything is checked here, before anything runs: an unknown factor, a value its
parser or the project rejects (schema or semantic checks of the changed project), a
replicate draw the project cannot re-seed, an empty design. Errors are
``STUDY:LINE:COL: <element>: message; fix`` lines (ProjectError, exit code 2).

Seeds: replicate ``r`` sets every draw named in ``<replicates vary>`` to
:func:`replicate_seed` (``draw``, ``r``), the same in every variant (common random
numbers: levels are compared on the same draws); draws not named keep the base's seeds.
"""

from __future__ import annotations

import difflib
import itertools
import os
import re
import zlib
from dataclasses import dataclass, replace
from pathlib import Path

from designer.project import model as m
from designer.project.problems import Problem, ProjectError
from designer.study.factors import DRAWS, FACTORS
from designer.study.spec import Study, Where
from designer.study.words import draw_words, factor_words, metric_words, named

#: most runs (variants × replicates) a study may have
MAX_RUNS = 100_000


@dataclass(frozen=True)
class Run:
    """One variant × replicate: the project to run and what it was made from."""

    run_id: str
    variant: int
    replicate: int
    levels: dict  # factor name → the value set for this variant (text)
    seeds: dict  # draw name → seed
    project: m.Project


@dataclass(frozen=True)
class Plan:
    study: Study
    base: m.Project
    base_dir: Path  # the folder the base project's relative paths start from
    runs: tuple[Run, ...]
    n_variants: int


def replicate_seed(draw: str, replicate: int) -> int:
    """The seed of ``draw`` in replicate ``replicate`` (0-based): a fixed 31-bit number."""
    return zlib.crc32(f"{draw}/{replicate}".encode()) & 0x7FFFFFFF


def _problem(study: Study, where: Where, tag: str, message: str, words: str | None = None,
             issue=None) -> ProjectError:
    """``FILE:LINE:COL: <tag>: message``; ``words``: what the Study panel says (no
    identifier of the study file; default ``message``), ``issue``: the project's issue a
    level makes (the panel words it as its Problems list)."""
    return ProjectError(str(study.source or "<study>"), [Problem(
        f"<{tag}>: {message}", where.line, where.column, issue=issue,
        words=message if words is None else words)])


def _untagged(problem: Problem) -> str:
    """A project problem's message without its leading ``<element>:`` (the line names the
    study's element)."""
    return re.sub(r"^<[^>\s]+>: ", "", problem.message)


def _words(problem: Problem) -> str:
    """What the panel says after "not valid:": nothing where it words the project's issue
    itself (as its Problems list), else the problem's words or message."""
    if problem.issue is not None:
        return ""
    return " " + (problem.words or _untagged(problem))


def _factor(name: str) -> str:
    """A factor as the command line names it: its words, then its identifier."""
    return named(factor_words(name), name)


def load_base(study: Study) -> tuple[m.Project, Path]:
    """The base project (schema and semantic checks) and the folder of its files."""
    from designer.project.load import load_project
    from designer.project.validate import semantic_problems
    from designer.project.xml_read import parse_project

    if study.base.file is not None:
        path = study.folder / study.base.file
        if not path.is_file():
            raise _problem(study, study.base.where, "base-project",
                           f"the base project '{study.base.file}' does not exist (relative "
                           "to the study file's folder); fix the path")
        return load_project(path), path.parent
    source = str(study.source or "<study>")
    project, smap = parse_project(study.base.inline_xml, source)
    problems = semantic_problems(project, study.folder, smap)
    if problems:
        raise ProjectError(source, problems)
    return project, study.folder


def _project_problems(project: m.Project, base_dir: Path) -> list[Problem]:
    """Schema and semantic problems of a changed project."""
    from designer.project.model_to_xml import project_to_bytes
    from designer.project.validate import semantic_problems
    from designer.project.xml_read import parse_project

    try:
        parse_project(project_to_bytes(project), "<variant>")
    except ProjectError as error:
        return error.problems
    return semantic_problems(project, base_dir)


def _apply(study: Study, project: m.Project, base_dir: Path, name: str, text: str):
    spec = next(f for f in study.factors if f.name == name)
    factor = FACTORS[name]
    try:
        value = factor.parse(text)
        if name == "texture-file":  # relative to the study file; the project needs its own
            value = os.path.relpath(study.folder / value, base_dir)
        changed = factor.set(project, value)
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        said = f"value '{text}' is not usable: {error}; expected: {factor.doc}"
        raise _problem(study, spec.values_where, "values", f"{_factor(name)}: {said}",
                       f"“{factor_words(name)}”: {said}") from None
    return changed


def _check_factors(study: Study) -> None:
    if not study.factors:
        raise _problem(study, study.where, "study",
                       "the design is empty: it varies no factor; add at least one factor "
                       "with its levels ('designer study factors' lists them)",
                       "the design is empty: it varies no factor; add one with its levels")
    seen = set()
    for f in study.factors:
        if f.name not in FACTORS:
            close = difflib.get_close_matches(f.name, FACTORS, n=1)
            hint = f"did you mean {_factor(close[0])}? " if close else ""
            raise _problem(study, f.where, "factor",
                           f"unknown factor '{f.name}'; {hint}'designer study factors' "
                           "lists every factor",
                           f"unknown factor '{f.name}'" + (
                               f" (did you mean “{factor_words(close[0])}”?)" if close
                               else ""))
        if f.name in seen:
            said = "is varied twice; merge its levels into one"
            raise _problem(study, f.where, "factor", f"{_factor(f.name)} {said}",
                           f"“{factor_words(f.name)}” {said}")
        seen.add(f.name)
        if len(set(f.values)) != len(f.values):
            said = "a level is repeated; list each level once"
            raise _problem(study, f.values_where, "values", f"{_factor(f.name)}: {said}",
                           f"“{factor_words(f.name)}”: {said}")


def plan_study(study: Study) -> Plan:
    """Every run of the study, each project checked; ProjectError before anything runs."""
    from designer.study.results import METRIC_COLUMNS

    _check_factors(study)
    for metric in study.metrics:
        if metric not in METRIC_COLUMNS:
            close = difflib.get_close_matches(metric, METRIC_COLUMNS, n=1)
            raise _problem(study, study.where, "metrics",
                           f"unknown metric '{metric}'"
                           + (f"; did you mean {named(metric_words(close[0]), close[0])}?"
                              if close else "")
                           + "; a metric is a column of the study's results (its list is "
                           "in docs/study.md)",
                           f"unknown metric '{metric}'" + (
                               f" (did you mean “{metric_words(close[0])}”?)" if close
                               else ""))
    base, base_dir = load_base(study)
    names = [f.name for f in study.factors]
    if study.design == "full-factorial":
        combos = [dict(zip(names, c, strict=True))
                  for c in itertools.product(*(f.values for f in study.factors))]
    else:
        combos = [{}] + [{f.name: v} for f in study.factors for v in f.values]
    n_runs = len(combos) * study.replicates.count
    if n_runs > MAX_RUNS:
        raise _problem(study, study.where, "study",
                       f"{n_runs} runs are too many (at most {MAX_RUNS}); use fewer levels")
    variants: list[tuple[dict, m.Project]] = []
    checked: dict[tuple[str, str], None] = {}
    for combo in combos:
        project = base
        for name, text in combo.items():
            project = _apply(study, project, base_dir, name, text)
        key = _identity(project)
        if any(_identity(p) == key for _, p in variants):
            continue  # a level equal to the base is the base variant
        for name, text in combo.items():
            if (name, text) in checked and study.design == "one-at-a-time":
                continue
            problems = _project_problems(project, base_dir)
            if problems:
                spec = next(f for f in study.factors if f.name == name)
                said = f"the level '{text}' makes a project that is not valid:"
                raise _problem(study, spec.values_where, "values",
                               f"{_factor(name)}: {said} {_untagged(problems[0])}",
                               f"“{factor_words(name)}”: {said}{_words(problems[0])}",
                               problems[0].issue)
            checked[(name, text)] = None
        if not combo:
            problems = _project_problems(project, base_dir)
            if problems:
                raise _problem(study, study.base.where, "base-project",
                               f"the base project is not valid: {_untagged(problems[0])}",
                               f"the base project is not valid:{_words(problems[0])}",
                               problems[0].issue)
        variants.append((combo, project))
    # one combination is a study of one run (measured, no effect estimated); several
    # that all collapse onto the base are a mistake
    if len(variants) < 2 and len(combos) > 1:
        raise _problem(study, study.where, "study",
                       "the design is empty: every level equals the base project; give "
                       "levels that differ from it")
    runs = []
    for v, (combo, project) in enumerate(variants):
        levels = {f.name: combo.get(f.name, _text(FACTORS[f.name].get(base)))
                  for f in study.factors}
        for r in range(study.replicates.count):
            seeds, seeded = {}, project
            for draw in study.replicates.vary:
                seeds[draw] = replicate_seed(draw, r)
                try:
                    seeded = DRAWS[draw][1](seeded, seeds[draw])
                except ValueError as error:
                    said = f"{error}; do not re-draw it in every replicate"
                    raise _problem(study, study.replicates.where, "replicates",
                                   f"{named(draw_words(draw), draw)}: {said}",
                                   f"“{draw_words(draw)}”: {said}") from None
            runs.append(Run(f"v{v:03d}-r{r:02d}", v, r, levels, seeds, seeded))
    return Plan(study, base, base_dir, tuple(runs), len(variants))


def _text(value) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return f"{value:g}"
    return "" if value is None else str(value)


def _identity(project: m.Project) -> m.Project:
    return replace(project, name="", description=None)
