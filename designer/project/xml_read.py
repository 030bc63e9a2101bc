"""Read a project file: size and content checks, safe XML parsing, version, XSD, model.

Every failure becomes a :class:`ProjectError` listing located problems; no parser
exception reaches the caller. Parsing is safe: no DTDs, entities or network access,
no huge-tree mode, and files above :data:`MAX_PROJECT_BYTES` are refused before
they are read.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from lxml import etree

from designer.project import model as m
from designer.project.problems import Problem, ProjectError, SourceMap
from designer.project.schema import (
    NAMESPACE,
    NAMESPACE_PREFIX,
    SUPPORTED_VERSIONS,
    xml_schema,
)
from designer.project.xml_to_model import project_from_tree
from designer.project.xsd_messages import translate_xsd_error

#: project files larger than this are refused (a 10,000-photo project is ~1.5 MB)
MAX_PROJECT_BYTES = 32_000_000

_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")


def read_project_file(path: str | os.PathLike) -> tuple[m.Project, SourceMap]:
    """Read and schema-validate ``path``; the model and where each part came from.

    Raises ProjectError (exit code 2) for anything but a schema-valid project file.
    Semantic checks are separate: see ``designer.project.load.load_project``.
    """
    data = read_xml_file(path, "project", "create one with 'designer new FILE --template "
                         "survey'")
    return parse_project(data, str(path))


def read_xml_file(path: str | os.PathLike, element: str, create_hint: str) -> bytes:
    """The bytes of a project or study file; ProjectError naming ``<element>`` when it is
    missing, not a regular file, too large or unreadable (``create_hint`` says how to
    make one)."""
    path = Path(path)
    source = str(path)
    try:
        size = path.stat().st_size
        if not path.is_file():
            raise ProjectError(source, [Problem(
                f"<{element}>: this is not a regular file; give the path of a {element} XML "
                "file", words=f"this is a folder or a device, not a {element} file; choose "
                f"a {element} file")])
        if size > MAX_PROJECT_BYTES:
            raise ProjectError(source, [_too_big(size, element)])
        return path.read_bytes()
    except FileNotFoundError:
        raise ProjectError(source, [Problem(
            f"<{element}>: no such file; check the path, or {create_hint}",
            words="there is no such file; check its name and folder")]) from None
    except OSError as error:
        why = error.strerror or error
        raise ProjectError(source, [Problem(
            f"<{element}>: cannot read the file ({why}); check its permissions",
            words=f"the file cannot be read ({why}); check its permissions")]) from None


def read_project(path: str | os.PathLike) -> m.Project:
    """The schema-valid model of ``path`` (no semantic checks)."""
    return read_project_file(path)[0]


def parse_project(data: bytes, source: str = "<memory>") -> tuple[m.Project, SourceMap]:
    """Parse project XML bytes into the model; ProjectError on any problem."""
    root, text = parse_tree(data, source)
    smap = SourceMap(text)
    schema = xml_schema()
    if not schema.validate(root.getroottree()):
        problems = [translate_xsd_error(e, root, smap) for e in schema.error_log]
        problems.sort(key=lambda p: (p.line, p.column))
        raise ProjectError(source, _dedupe(problems))
    return project_from_tree(root, smap), smap


def parse_tree(data: bytes, source: str) -> tuple[etree._Element, str]:
    """The root element of a well-formed project of a supported version, and its text."""
    if len(data) > MAX_PROJECT_BYTES:
        raise ProjectError(source, [_too_big(len(data))])
    problem = _content_problem(data)
    if problem:
        raise ProjectError(source, [problem])
    parser = etree.XMLParser(
        resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False,
        remove_comments=False, collect_ids=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as error:
        raise ProjectError(source, [_syntax_problem(error)]) from None
    text = data.decode("utf-8", errors="replace")
    if root.getroottree().docinfo.doctype:
        at = text.find("<!DOCTYPE")
        line = text.count("\n", 0, at) + 1 if at >= 0 else 1
        column = at - text.rfind("\n", 0, at) if at >= 0 else 1
        raise ProjectError(source, [Problem(
            "<!DOCTYPE>: document type declarations (and entities) are not allowed in "
            "project files; remove the DOCTYPE declaration", line, column,
            words=f"line {line} declares a document type (DOCTYPE), which project files "
                  "may not have; remove it in a text editor")])
    _check_root(root, source)
    return root, text


def _too_big(size: int, element: str = "project") -> Problem:
    text = (f"the file is {size / 1e6:.1f} MB, larger than the "
            f"{MAX_PROJECT_BYTES / 1e6:.0f} MB limit for {element} files; keep large data "
            "(DEMs, meshes, textures) in separate files referenced from the project")
    return Problem(f"<{element}>: {text}", words=text)


def _content_problem(data: bytes) -> Problem | None:
    if not data.strip():
        return Problem("<project>: the file is empty; create a project with 'designer new "
                       "FILE --template survey'",
                       words="the file is empty; start a project from a template (File › "
                             "New)")
    if data.startswith(_UTF16_BOMS):
        return None  # UTF-16 text is legal XML; the parser reads it
    head = data[:65536]
    nul = head.find(b"\x00")
    if nul >= 0:
        text = (f"binary data (a zero byte at offset {nul}), not an XML project file; check "
                "that you gave the right file")
        return Problem(f"<project>: {text}", words=text)
    start = head.lstrip(b"\xef\xbb\xbf \t\r\n")[:1]
    if start != b"<":
        text = ("not an XML file (it does not start with '<'); check that you gave a designer "
                "project file")
        return Problem(f"<project>: {text}", words=text)
    return None


def _syntax_problem(error: etree.XMLSyntaxError) -> Problem:
    line, column = error.position if error.position else (1, 1)
    msg = re.sub(r",? line \d+, column \d+$", "", (error.msg or str(error)).strip())
    mismatch = re.match(r"Opening and ending tag mismatch: (\S+) line (\d+) and (\S+)", msg)
    if mismatch:
        opened, opened_line, closed = mismatch.groups()
        msg = (f"element '{opened}' opened on line {opened_line} is closed as '{closed}'; "
               f"close '{opened}' first")
    elif msg.startswith("Entity"):
        msg += "; write '&' as &amp; and '<' as &lt; (entities are not supported)"
    else:
        msg += "; fix the XML syntax here (every tag closed, attribute values quoted)"
    line, column = max(int(line or 1), 1), max(int(column or 1), 1)
    return Problem(f"<xml>: malformed XML: {msg}", line, column,
                   words=f"the file is not well-formed XML at line {line}, column {column}: "
                         f"{msg}; correct it in a text editor")


def _check_root(root: etree._Element, source: str) -> None:
    qname = etree.QName(root)
    line = root.sourceline or 1
    version = root.get("schema-version")
    supported = ", ".join(SUPPORTED_VERSIONS)
    newer = ("the file was written for a newer designer (project format {}; this one "
             f"reads {supported}); open it with a newer designer")
    if qname.localname != "project":
        raise ProjectError(source, [Problem(
            f"<{qname.localname}>: the root element must be a designer project (element "
            f"'project' in namespace {NAMESPACE}, schema-version {SUPPORTED_VERSIONS[-1]}), "
            f"not '{qname.localname}'; this is not a designer project file", line, 1,
            words=f"this is not a designer project file (it holds a '{qname.localname}', "
                  "not a project); open a project file, or start one from a template (File "
                  "› New)")])
    ns = qname.namespace
    if ns and ns.startswith(NAMESPACE_PREFIX) and ns != NAMESPACE:
        found = f"schema-version {version}" if version else f"namespace {ns}"
        raise ProjectError(source, [Problem(
            f"<project>: {found} is not supported; this designer reads schema versions "
            f"{supported} (namespace {NAMESPACE}); use a newer designer for this file",
            line, 1, words=newer.format(version or ns.rsplit(":", 1)[-1]))])
    if ns != NAMESPACE:
        where = f"namespace '{ns}'" if ns else "no namespace"
        raise ProjectError(source, [Problem(
            f"<project>: the root element is in {where}; a designer project needs the "
            f"namespace {NAMESPACE} on its root element", line, 1,
            words="the file is not in designer's project format (its namespace is "
                  f"{'missing' if not ns else repr(ns)}); open a file saved by designer, or "
                  f"give its first element the namespace {NAMESPACE} in a text editor")])
    if version is None:
        raise ProjectError(source, [Problem(
            "<project>: the schema-version attribute is missing; give the root element "
            f"schema-version {SUPPORTED_VERSIONS[-1]} (supported: {supported})", line, 1,
            words="the file does not say which version of the project format it is "
                  f"written in; give its first element the schema version "
                  f"{SUPPORTED_VERSIONS[-1]} in a text editor")])
    if version.strip() not in SUPPORTED_VERSIONS:
        raise ProjectError(source, [Problem(
            f"<project>: schema-version '{version}' is not supported; this designer reads "
            f"schema versions {supported}; use a newer designer for files of a newer "
            "version", line, 1, words=newer.format(version.strip()))])


def _dedupe(problems: list[Problem]) -> list[Problem]:
    seen: set[tuple[int, int, str]] = set()
    out = []
    for p in problems:
        key = (p.line, p.column, p.message)
        if key not in seen:
            seen.add(key)
            out.append(p)
    return out
