"""The Study panel's words for a study's identifiers (:mod:`designer.study.words`) and
its problems as the panel lists them: in words, no identifier and no element of the
study file."""

from __future__ import annotations

from designer.study.words import (  # noqa: F401 (the panel's words, from one place)
    DRAW_WORDS,
    FACTOR_WORDS,
    STAGE_WORDS,
    draw_words,
    factor_words,
    metric_words,
    tip,
)


def study_problem_lines(error) -> list[str]:
    """The problems of a study (a ProjectError of :mod:`designer.study`) as the Study
    panel lists them: the place in the study file, then what is wrong in words (no
    identifier, no element); a level that makes the project invalid is followed by the
    project's problem as the Problems list words it."""
    from designer.gui.state.wording import issue_line, problem_text

    lines, places = [], set()
    for problem in error.problems:
        place = (problem.line, problem.column)
        if place in places:  # the schema's second word on the same value
            continue
        places.add(place)
        issue = problem.issue
        choices = [_words(c) for c in (issue.choices or ())] if issue is not None else []
        located = f"{error.source}:{problem.line}:{problem.column}"
        if problem.words is not None and place != (1, 1):  # a study's own: in words
            worded = f" {issue_line(issue)}" if issue is not None else ""
            lines.append(f"{located}: {problem.words}{worded}")
        elif choices and all(choices):  # a hand-edited name: the names in words
            lines.append(f"{located}: “{issue.value}” is not one of: {'; '.join(choices)}")
        else:
            lines.append(problem_text(problem, error.source))
    return lines


def _words(identifier: str) -> str:
    """A factor's, draw's or metric's words ("" for another name)."""
    for words in (draw_words, factor_words, metric_words):
        try:
            return words(identifier)
        except KeyError:
            pass
    return ""
