"""Write a study file from the study model (the inverse of :mod:`designer.study.xml`).

:func:`study_to_xml` gives text the reader reads back to an equal study (factors, their
levels, design, replicates, metrics, description and the base project: a file path
relative to the study file, or the inline project). Levels are written as ``<values>``,
or as the ``<range>`` they were given as while they still are that range.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from designer.project.schema import NAMESPACE, SUPPORTED_VERSIONS
from designer.study.cost import DEFAULT_COST
from designer.study.spec import Study, range_levels


def _check_levels(study: Study) -> None:
    for f in study.factors:
        for value in f.values:
            if not value or any(c.isspace() for c in value):
                raise ValueError(f"factor {f.name}: level '{value}' is empty or has a space; "
                                 "levels are separated by spaces in a study file")


def study_to_xml(study: Study, base_file: str | None = None) -> str:
    """The study file's text; ``base_file`` overrides ``study.base.file`` (a path
    relative to the folder the study file is written to)."""
    _check_levels(study)
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<study xmlns="{NAMESPACE}" schema-version="{SUPPORTED_VERSIONS[-1]}" '
             f'name={quoteattr(study.name)}>']
    if study.description:
        lines.append(f"  <description>{escape(study.description)}</description>")
    file = base_file if base_file is not None else study.base.file
    if file is not None:
        lines.append(f"  <base-project file={quoteattr(Path(file).as_posix())}/>")
    elif study.base.inline_xml is not None:
        inline = study.base.inline_xml.decode("utf-8").strip()
        if inline.startswith("<?xml"):
            inline = inline.split("?>", 1)[1].strip()
        lines += ["  <base-project>", inline, "  </base-project>"]
    else:
        raise ValueError("the study has no base project (a file or an inline project)")
    for f in study.factors:
        lines.append(f"  <factor name={quoteattr(f.name)}>")
        if f.description:
            lines.append(f"    <description>{escape(f.description)}</description>")
        if f.range_spec is not None and range_levels(*f.range_spec) == tuple(f.values):
            start, stop, step = (f"{v:.15g}" for v in f.range_spec)
            lines.append(f'    <range start="{start}" stop="{stop}" step="{step}"/>')
        else:
            lines.append(f"    <values>{escape(' '.join(f.values))}</values>")
        lines.append("  </factor>")
    lines.append(f"  <design>{study.design}</design>")
    rep = study.replicates
    vary = f" vary={quoteattr(' '.join(rep.vary))}" if rep.vary else ""
    lines.append(f'  <replicates count="{int(rep.count)}"{vary}/>')
    if study.metrics:
        lines.append(f"  <metrics>{escape(' '.join(study.metrics))}</metrics>")
    if study.cost != DEFAULT_COST:
        lines.append(f"  <cost>{escape(study.cost)}</cost>")
    lines.append("</study>")
    return "\n".join(lines) + "\n"


def write_study(study: Study, path: str | os.PathLike, base_path: Path | None = None) -> Path:
    """Write ``study`` to ``path`` atomically. ``base_path``: the base project file, written
    relative to the study file's folder (else the study's own base is kept)."""
    from designer.atomic import write_text_atomic

    path = Path(path)
    base_file = None
    if base_path is not None:
        try:
            base_file = os.path.relpath(Path(base_path).resolve(), path.resolve().parent)
        except ValueError:  # another drive
            base_file = str(Path(base_path).resolve())
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(path, study_to_xml(study, base_file))
    return path
