"""Write a template project and its companion files (``designer new``)."""

from __future__ import annotations

import os
from pathlib import Path

from designer.atomic import write_bytes_atomic
from designer.errors import DesignerError
from designer.project.load import validate_project
from designer.project.model_to_xml import project_to_bytes
from designer.project.templates import TEMPLATE_NAMES, template


def write_template(path: str | os.PathLike, name: str, force: bool = False) -> list[Path]:
    """Write template ``name`` to ``path`` (companions beside it); the paths written.

    Refuses (DesignerError, exit 2) to overwrite any existing file unless ``force``.
    The project file is written last, so it never refers to a missing companion.
    """
    if name not in TEMPLATE_NAMES:
        raise DesignerError(f"unknown template '{name}'; choose one of "
                            + ", ".join(TEMPLATE_NAMES))
    path = Path(path)
    if path.suffix.lower() != ".xml":
        raise DesignerError(f"{path}: a project file name must end in .xml")
    tpl = template(name)
    return write_new_project(path, tpl.project, tpl.files, force, f"template {name}")


def write_new_project(path: str | os.PathLike, project, files: dict[str, bytes],
                      force: bool, source: str, check_files: bool = False) -> list[Path]:
    """Validate ``project`` and write it to ``path`` with its companion ``files`` (bytes
    by path relative to the project's folder); the paths written, the project last.

    Refuses (DesignerError) to overwrite any existing file unless ``force``. With
    ``check_files`` the files the project refers to are checked too (they must exist).
    """
    path = Path(path)
    if path.suffix.lower() != ".xml":
        raise DesignerError(f"{path}: a project file name must end in .xml")
    if check_files:
        # Paths relative to the project's folder resolve only once the folder exists.
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise DesignerError(f"{path}: cannot create its folder ({error.strerror or error})"
                                ) from None
    validate_project(project, base_dir=path.parent if check_files else None, source=source)
    folder = path.parent
    targets = [folder / rel for rel in files] + [path]
    existing = [p for p in targets if p.exists()]
    if existing and not force:
        raise DesignerError(", ".join(str(p) for p in existing)
                            + (" exists" if len(existing) == 1 else " exist")
                            + "; choose another name or add --force to overwrite")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        for rel, data in files.items():
            write_bytes_atomic(folder / rel, data)
        write_bytes_atomic(path, project_to_bytes(project))
    except OSError as error:
        raise DesignerError(f"{path}: cannot write ({error.strerror or error}); check the "
                            "folder and its permissions") from None
    return targets
