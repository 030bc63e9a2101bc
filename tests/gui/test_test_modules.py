"""The GUI tests share code through ``tests/gui/helpers.py`` only."""

from __future__ import annotations

import ast
from pathlib import Path


def test_no_test_module_imports_another_test_module_or_a_conftest():
    here = Path(__file__).parent
    offending = []
    for path in sorted(here.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = ([node.module or ""] if isinstance(node, ast.ImportFrom)
                     else [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            for name in names:
                last = name.rsplit(".", 1)[-1]
                if last.startswith("test_") or last == "conftest":
                    offending.append(f"{path.name}:{node.lineno}: imports {name}")
    assert not offending, "\n".join(offending)
