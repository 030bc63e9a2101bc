"""The XML schema of project files: where it is, its namespace and versions, loading it.

The schema is one file, ``designer/schema/designer-project-<version>.xsd``, inside the
package so that an installed designer finds it through ``importlib.resources``;
``schema/`` at the top of the repository is a link to that folder.
"""

from __future__ import annotations

import functools
from importlib import resources
from pathlib import Path

#: XML namespace of project files; the major version is part of it
NAMESPACE = "urn:designer:project:1"
#: namespaces of every major version, past or future, start with this
NAMESPACE_PREFIX = "urn:designer:project:"
#: schema versions this designer reads (the ``schema-version`` attribute)
SUPPORTED_VERSIONS = ("1.0",)
#: the version written by this designer
CURRENT_VERSION = "1.0"


def schema_filename(version: str = CURRENT_VERSION) -> str:
    return f"designer-project-{version}.xsd"


def schema_path(version: str = CURRENT_VERSION) -> Path:
    """Path of the packaged XSD for ``version`` (a real file inside the package)."""
    resource = resources.files("designer") / "schema" / schema_filename(version)
    return Path(str(resource))


@functools.cache
def xml_schema(version: str = CURRENT_VERSION):
    """The compiled lxml ``XMLSchema`` (loaded once per process)."""
    from lxml import etree

    parser = etree.XMLParser(resolve_entities=False, no_network=True)
    return etree.XMLSchema(etree.parse(str(schema_path(version)), parser))


def q(local_name: str) -> str:
    """Clark notation ``{namespace}name`` of an element of the project namespace."""
    return f"{{{NAMESPACE}}}{local_name}"
