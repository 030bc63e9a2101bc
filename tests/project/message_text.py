"""What the walks of messages read (tests/project/test_message_walk.py,
tests/study/test_study_message_walk.py): the patterns of raw XML and Python identifiers,
and the sentences of a module."""

from __future__ import annotations

import ast
import re
from pathlib import Path

#: an XML element or end tag, or an attribute written as in the file
XML = re.compile(r"</?[A-Za-z!][\w.:-]*|\b[a-z][\w-]*=[\"'{]")
#: the command line's locator: ``<element>:`` after FILE:LINE:COL (or first)
LOCATOR = re.compile(r"(^|\{\}: |: )<[\w!.-]+>: ")
#: a Python identifier with an underscore (``focal_length_mm``); file paths, numbers
#: and the names of files (``pose_noise.csv``) aside
SNAKE = re.compile(r"(?<![\w./\\{%-])[a-z][a-z0-9]*(?:_[a-z0-9]+)+(?![\w./\\(-])")


def _literal(node) -> str | None:
    """The text of a string literal, an f-string's placeholders as {}."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.JoinedStr):
        return "".join(v.value if isinstance(v, ast.Constant) else "{}" for v in node.values)
    return None


def _sentences(path: Path):
    """(line, text) of every literal with a space in it, docstrings and the parts of
    f-strings aside (the whole f-string is read)."""
    tree = ast.parse(path.read_text())
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.FunctionDef | ast.ClassDef) and node.body \
                and isinstance(node.body[0], ast.Expr):
            skip.add(id(node.body[0].value))
        if isinstance(node, ast.JoinedStr):
            skip.update(id(v) for v in node.values)
        if isinstance(node, ast.Call) and getattr(node.func, "attr", "") in (
                "compile", "match", "search", "sub", "finditer", "fullmatch"):
            skip.update(id(a) for a in node.args[:1])  # regular expressions
    for node in ast.walk(tree):
        text = _literal(node)
        if text is not None and " " in text and id(node) not in skip:
            yield node.lineno, text
