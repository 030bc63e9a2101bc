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

from typing import TYPE_CHECKING

from designer._lazy import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    "NAMESPACE": "designer.project.schema",
    "Problem": "designer.project.problems",
    "Project": "designer.project.model",
    "ProjectError": "designer.project.problems",
    "SUPPORTED_VERSIONS": "designer.project.schema",
    "TEMPLATE_NAMES": "designer.project.templates",
    "Template": "designer.project.templates",
    "load_project": "designer.project.load",
    "parse_project": "designer.project.xml_read",
    "project_to_bytes": "designer.project.model_to_xml",
    "read_project": "designer.project.xml_read",
    "read_project_file": "designer.project.xml_read",
    "schema_path": "designer.project.schema",
    "semantic_problems": "designer.project.validate",
    "template": "designer.project.templates",
    "validate_project": "designer.project.load",
    "write_project": "designer.project.model_to_xml",
})

if TYPE_CHECKING:
    from designer.project.load import load_project, validate_project
    from designer.project.model import Project
    from designer.project.model_to_xml import project_to_bytes, write_project
    from designer.project.problems import Problem, ProjectError
    from designer.project.schema import NAMESPACE, SUPPORTED_VERSIONS, schema_path
    from designer.project.templates import TEMPLATE_NAMES, Template, template
    from designer.project.validate import semantic_problems
    from designer.project.xml_read import parse_project, read_project, read_project_file
