"""Self-contained reports: Markdown with PNG figures, plus summary.json, written atomically."""

from __future__ import annotations

import json
import math
import platform
from dataclasses import asdict, dataclass
from pathlib import Path

from designer import __version__
from designer.atomic import write_text_atomic


@dataclass(frozen=True)
class Criterion:
    """One pass/fail criterion: what is measured, the measured value and the limit."""

    name: str
    description: str
    value: float | str
    limit: str
    passed: bool

    def to_dict(self) -> dict:
        return asdict(self)


class Report:
    """A Markdown document built section by section."""

    def __init__(self, title: str) -> None:
        self.lines = [f"# {title}", ""]

    def heading(self, text: str, level: int = 2) -> None:
        self.lines += [f"{'#' * level} {text}", ""]

    def para(self, text: str) -> None:
        self.lines += [text.strip(), ""]

    def bullets(self, items: list[str]) -> None:
        self.lines += [f"* {item}" for item in items] + [""]

    def table(self, header: list[str], rows: list[list]) -> None:
        self.lines.append("| " + " | ".join(header) + " |")
        self.lines.append("|" + "|".join("---" for _ in header) + "|")
        for row in rows:
            self.lines.append("| " + " | ".join(_cell(c) for c in row) + " |")
        self.lines.append("")

    def figure(self, file_name: str, caption: str) -> None:
        self.lines += [f"![{caption}]({file_name})", "", f"*{caption}*", ""]

    def opening(self, criteria: list[Criterion], question: str) -> bool:
        """A validation's first paragraphs: its result (PASSED when every criterion
        passed, else FAILED), the question it answers, then the heading of how it was
        measured. Returns whether every criterion passed."""
        passed = all(c.passed for c in criteria)
        self.para(f"**Result: {'PASSED' if passed else 'FAILED'}.**")
        self.para(question)
        self.heading("How it was measured")
        return passed

    def criteria(self, criteria: list[Criterion]) -> None:
        self.table(["criterion", "measured", "limit", "result"],
                   [[f"**{c.name}**: {c.description}", c.value, c.limit,
                     "PASS" if c.passed else "**FAIL**"] for c in criteria])

    def text(self) -> str:
        return "\n".join(self.lines).rstrip() + "\n"


def _cell(value) -> str:
    if isinstance(value, float):
        if math.isnan(value):
            return "–"
        return f"{value:.4g}"
    return str(value).replace("|", "\\|")


def fmt_p(p: float) -> str:
    """A p-value as text: 3 significant digits, or '< 1e-300'."""
    return "< 1e-300" if p == 0 else f"{p:.3g}"


def write_report(out_dir: Path, report: Report, summary: dict) -> tuple[Path, Path]:
    """Write ``report.md`` and ``summary.json`` (with versions added) into ``out_dir``."""
    out_dir.mkdir(parents=True, exist_ok=True)
    summary = dict(summary, designer_version=__version__, python=platform.python_version(),
                   report="report.md")
    md, js = out_dir / "report.md", out_dir / "summary.json"
    write_text_atomic(md, report.text())
    write_text_atomic(js, json.dumps(summary, indent=1, default=_json_default) + "\n")
    return md, js


def _json_default(value):
    if hasattr(value, "to_dict"):
        return value.to_dict()
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"cannot write {type(value).__name__} to JSON")
