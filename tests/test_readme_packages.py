"""The README's "What is inside" table names every package of designer."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_the_readme_table_lists_every_package():
    readme = (ROOT / "README.md").read_text()
    table = readme.split("## What is inside", 1)[1].split("\n\n", 2)[1]
    listed = set(re.findall(r"^\| `designer/(\w+)/` \|", table, re.M))
    packages = {p.name for p in (ROOT / "designer").iterdir()
                if p.is_dir() and not p.name.startswith(("_", "."))
                and (p.name == "schema" or (p / "__init__.py").is_file())}
    assert packages, "no package found"
    assert listed == packages
