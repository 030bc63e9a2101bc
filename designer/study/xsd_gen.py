"""The study XSD (``schema/designer-study-1.0.xsd``), generated whole from the study model.

As the project XSD (designer.project.xsd_gen): the elements and attributes come from the
classes of :mod:`designer.study.spec` and their XML declarations
(designer.project.declare_structure); the named simple types are stated here, among them
``Draw``, one ``xs:enumeration`` per replicate draw of :data:`designer.study.factors.DRAWS`
(declared on the seeds they re-seed, ``attr(draw=...)``), documented by the draw's
documentation, and ``Cost``, the names of :data:`designer.study.cost.COSTS`.
``python -m designer.study.xsd_gen`` rewrites the committed file; ``--check`` exits 1
when it differs from the model.
"""

from __future__ import annotations

import sys

from designer.project.declare_structure import ListOf
from designer.project.xsd_types import NamedSimpleType

STUDY_DOC = """\
designer study, schema version 1.0 (namespace urn:designer:project:1, the namespace of
project files).

A study varies named parameters (factors) of a base project across many virtual
surveys, with replicates that re-draw chosen random errors, and reports accuracy and
its cost (flight minutes, images, GCPs, CPU or wall seconds: <cost>). Run it with:
designer study run STUDY.xml -o DIR. The factor names, what each one changes and
whether it needs new images are listed by 'designer study factors' and in
docs/studies.md.
"""


def simple_types(draws: dict[str, str], costs: tuple[str, ...]) -> tuple[NamedSimpleType, ...]:
    """The study XSD's named simple types, its ``Draw`` type listing ``draws`` (name →
    documentation) and its ``Cost`` type ``costs``."""
    number = r"[+\-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+\-]?[0-9]+)?"
    return (
        NamedSimpleType("Name", "", "xs:string",
                        (("pattern", r"[A-Za-z0-9][A-Za-z0-9_.+\-]*"), ("maxLength", "100"))),
        NamedSimpleType("FiniteDecimal", "", "xs:double", (("pattern", number),)),
        NamedSimpleType("Draw", "A random draw a replicate re-seeds (designer study factors "
                        "lists them).", "xs:string",
                        tuple(("enumeration", name, doc) for name, doc in draws.items())),
        NamedSimpleType("DrawList", "", ListOf("d:Draw"), ()),
        NamedSimpleType("MetricList", "", ListOf("d:Name"), ()),
        NamedSimpleType("ValueList", "", ListOf("xs:string"), (("minLength", "1"),)),
        NamedSimpleType("Cost", "", "xs:string",
                        tuple(("enumeration", name) for name in costs)),
    )


def generate(draws: dict[str, str] | None = None) -> str:
    """The study XSD, its replicate draws ``draws`` (name → documentation; default: DRAWS)."""
    from designer.project.xsd_gen import schema_text
    from designer.study.cost import COSTS
    from designer.study.spec import Study

    if draws is None:
        from designer.study.factors import DRAWS

        draws = {name: doc for name, (doc, _) in DRAWS.items()}
    return schema_text(Study, doc=STUDY_DOC, simple_types=simple_types(draws, tuple(COSTS)),
                       made_by="designer.study.xsd_gen", source="designer/study/spec.py")


def main(argv: list[str] | None = None) -> int:
    from designer.project.xsd_gen import regenerate
    from designer.study.xml import study_schema_path

    return regenerate(argv, prog="python -m designer.study.xsd_gen",
                      description="Write the study XSD from the study model.",
                      default_xsd=study_schema_path(),
                      generate_xsd=lambda _text: generate(),
                      differs="the XSD differs from the model")

if __name__ == "__main__":
    sys.exit(main())
