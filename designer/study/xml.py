"""Read a study file: safe XML parsing, the study XSD, then the model.

Errors are :class:`~designer.project.problems.ProjectError` lines
``STUDY:LINE:COL: <element>: message; fix`` (exit code 2), as for project files. An
inline base project is validated against the project schema with its own line numbers.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

from lxml import etree

from designer.project.problems import Problem, ProjectError, SourceMap
from designer.project.schema import NAMESPACE, SUPPORTED_VERSIONS
from designer.project.xml_read import _content_problem, _syntax_problem, read_xml_file
from designer.project.xsd_info import SchemaInfo
from designer.project.xsd_messages import translate_xsd_error
from designer.study.cost import DEFAULT_COST
from designer.study.spec import (
    DEFAULT_METRICS,
    BaseProject,
    FactorSpec,
    Replicates,
    Study,
    Where,
    range_levels,
)

STUDY_SCHEMA = "designer-study-1.0.xsd"


def study_schema_path() -> Path:
    from importlib import resources

    return Path(str(resources.files("designer") / "schema" / STUDY_SCHEMA))


@functools.cache
def _schema():
    parser = etree.XMLParser(resolve_entities=False, no_network=True)
    tree = etree.parse(str(study_schema_path()), parser)
    return etree.XMLSchema(tree), SchemaInfo(tree)


def read_study(path: str | os.PathLike) -> Study:
    """The study in ``path``, schema-valid; ProjectError (exit 2) for anything else.

    Factor names and values are checked against the base project by
    :func:`designer.study.design.plan_study`.
    """
    path = Path(path)
    data = read_xml_file(path, "study", "write an example with 'designer study new FILE "
                         "--template gcp-count'")
    return parse_study(data, str(path), path.resolve())


def parse_study(data: bytes, source: str = "<memory>", path: Path | None = None) -> Study:
    problem = _content_problem(data)
    if problem:
        def study(text: str) -> str:
            return (text.replace("<project>", "<study>").replace("a project", "a study")
                    .replace("project file", "study file").replace(
                        "(File › New)", "('designer study new')"))

        raise ProjectError(source, [Problem(study(problem.message),
                                            words=study(problem.words or problem.message))])
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False,
                             huge_tree=False, collect_ids=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as error:
        raise ProjectError(source, [_syntax_problem(error)]) from None
    if root.getroottree().docinfo.doctype:
        raise ProjectError(source, [Problem(
            "<!DOCTYPE>: document type declarations are not allowed; remove it",
            words="the file declares a document type (DOCTYPE), which study files may not "
                  "have; remove it in a text editor")])
    text = data.decode("utf-8", errors="replace")
    smap = SourceMap(text)
    _check_root(root, source)
    schema, info = _schema()
    if not schema.validate(root.getroottree()):
        problems = sorted({(p.line, p.column, p.message): p for p in (
            translate_xsd_error(e, root, smap, info) for e in schema.error_log)}.values(),
            key=lambda p: (p.line, p.column))
        raise ProjectError(source, problems)
    return _model(root, smap, text, source, path)


def _check_root(root: etree._Element, source: str) -> None:
    qname = etree.QName(root)
    if qname.localname != "study" or qname.namespace != NAMESPACE:
        raise ProjectError(source, [Problem(
            f"<{qname.localname}>: the root element must be a designer study (element "
            f"'study' in namespace {NAMESPACE}, schema-version {SUPPORTED_VERSIONS[-1]}, "
            f"with a name), not '{qname.localname}'; this is not a designer study file",
            root.sourceline or 1, 1,
            words=f"this is not a designer study file (it holds a '{qname.localname}', "
                  "not a study); open a study file, or start one with 'designer study new'")])
    version = (root.get("schema-version") or "").strip()
    if version and version not in SUPPORTED_VERSIONS:
        supported = ", ".join(SUPPORTED_VERSIONS)
        raise ProjectError(source, [Problem(
            f"<study>: schema-version '{version}' is not supported; this designer reads "
            f"schema versions {supported}; use a newer designer for files of a newer "
            "version", root.sourceline or 1, 1,
            words=f"the file was written for a newer designer (study format {version}; "
                  f"this one reads {supported}); open it with a newer designer")])


def _where(smap: SourceMap, el: etree._Element, attr: str | None = None) -> Where:
    line, column = smap.position(el.sourceline or 1, etree.QName(el).localname, attr)
    return Where(line, column)


def _child(el: etree._Element, name: str) -> etree._Element | None:
    return el.find(f"{{{NAMESPACE}}}{name}")


def _text(el: etree._Element | None) -> str | None:
    return None if el is None else " ".join((el.text or "").split())


def _model(root, smap: SourceMap, text: str, source: str, path: Path | None) -> Study:
    base_el = _child(root, "base-project")
    inline = [c for c in base_el if isinstance(c.tag, str)]
    file = base_el.get("file")
    where = _where(smap, base_el)
    if (file is None) == (not inline):
        said = ("the base project is given both as a file and inside the study; keep one"
                if file else "the study names no base project; give its file, or put the "
                "project inside the study")
        raise ProjectError(source, [Problem(f"<base-project>: {said}", where.line,
                                            where.column, words=said)])
    inline_xml = None
    if inline:
        el = inline[0]
        # Leading line breaks keep the inline project's line numbers those of the study file.
        inline_xml = b"\n" * ((el.sourceline or 1) - 1) + etree.tostring(el)
    factors = []
    for f in root.iterfind(f"{{{NAMESPACE}}}factor"):
        values_el = _child(f, "values")
        range_spec = None
        if values_el is not None:
            values = tuple((values_el.text or "").split())
            values_where = _where(smap, values_el)
        else:
            r = _child(f, "range")
            range_spec = tuple(float(r.get(k)) for k in ("start", "stop", "step"))
            values = _range_values(r, smap, source)
            values_where = _where(smap, r)
        factors.append(FactorSpec(f.get("name"), values, _text(_child(f, "description")),
                                  _where(smap, f, "name"), values_where, range_spec))
    rep_el = _child(root, "replicates")
    replicates = Replicates() if rep_el is None else Replicates(
        int(rep_el.get("count")), tuple(dict.fromkeys((rep_el.get("vary") or "").split())),
        _where(smap, rep_el))
    metrics_el = _child(root, "metrics")
    metrics = tuple((metrics_el.text or "").split()) if metrics_el is not None else ()
    return Study(
        name=root.get("name"), base=BaseProject(file, inline_xml, where),
        factors=tuple(factors), design=_text(_child(root, "design")) or "one-at-a-time",
        replicates=replicates, metrics=metrics or DEFAULT_METRICS,
        description=_text(_child(root, "description")),
        cost=_text(_child(root, "cost")) or DEFAULT_COST, source=path,
        where=_where(smap, root))


def _range_values(r: etree._Element, smap: SourceMap, source: str) -> tuple[str, ...]:
    start, stop, step = (float(r.get(k)) for k in ("start", "stop", "step"))
    try:
        return range_levels(start, stop, step)
    except ValueError as error:
        where = _where(smap, r)
        said = f"the levels' range: {error}"
        raise ProjectError(source, [Problem(f"<range>: {said}", where.line, where.column,
                                            words=said)]) from None
