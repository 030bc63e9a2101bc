"""``python -m designer.project.attributes``: the attribute tables of every declared
element (designer.project.declare), as docs/attributes.md holds them."""

from __future__ import annotations

HEADER = """# Element attributes

Every declared element of a project file: each attribute's unit, range, default,
meaning and the study factor that varies it. Made from the model's declarations by
`python -m designer.project.attributes > docs/attributes.md` (a test checks it is
current); the XSD's attributes of these elements (schema/designer-project-1.0.xsd) are
generated from the same declarations by `python -m designer.project.xsd_gen`.
"""


def attribute_tables() -> str:
    from designer.project import model as m
    from designer.project.declare import attribute_table, declared_elements

    return HEADER + "".join("\n## " + attribute_table(cls).lstrip()
                            for cls in declared_elements(m.Project))


if __name__ == "__main__":
    print(attribute_tables(), end="")
