"""The project: an XML file describing one virtual survey, its model and its validation.

Public API::

    load_project(path)              -> Project   read + XSD + semantic checks (ProjectError)
    read_project(path)              -> Project   read + XSD only
    write_project(project, path)                 atomic write, schema order
    project_to_bytes(project)       -> bytes
    parse_project(data, source)     -> (Project, SourceMap)
    validate_project(project, base_dir=None)     semantic checks of an in-memory model
    semantic_problems(project, base_dir=None, smap=None) -> list[Problem]
    template(name)                  -> Template(project, files)

Frames and units: docs/conventions.md and the schema's documentation.
"""

from designer.project.load import load_project, validate_project
from designer.project.model import Project
from designer.project.model_to_xml import project_to_bytes, write_project
from designer.project.problems import Problem, ProjectError
from designer.project.schema import NAMESPACE, SUPPORTED_VERSIONS, schema_path
from designer.project.templates import TEMPLATE_NAMES, Template, template
from designer.project.validate import semantic_problems
from designer.project.xml_read import parse_project, read_project, read_project_file

__all__ = [
    "NAMESPACE",
    "SUPPORTED_VERSIONS",
    "TEMPLATE_NAMES",
    "Problem",
    "Project",
    "ProjectError",
    "Template",
    "load_project",
    "parse_project",
    "project_to_bytes",
    "read_project",
    "read_project_file",
    "schema_path",
    "semantic_problems",
    "template",
    "validate_project",
    "write_project",
]
