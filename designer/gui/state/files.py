"""Saving and creating project files for the designer window (Qt-free).

Save = serialise → validate exactly what would be written (XSD, then the semantic
checks, with line numbers of the file to be) → write atomically, or write nothing and
return the problems. Files the project references keep pointing at the same files
when it is saved into another folder (relative paths are rewritten), and a project
new from a template has its companion files (a texture, a mesh) copied beside it.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from designer.atomic import write_bytes_atomic
from designer.gui.state.field_places import PANEL_KEYWORDS, panel_for_tag
from designer.gui.state.wording import problem_text
from designer.project import model as m
from designer.project import parse_project, project_to_bytes, semantic_problems, template
from designer.project.declare import declared
from designer.project.files import resolve
from designer.project.problems import ProjectError


@dataclass(frozen=True)
class SavePlan:
    """What a save would write: the XML bytes and the (possibly rebased) project, or the
    problems that stop it (``FILE:LINE:COL: <element>: message``)."""

    path: Path
    project: m.Project
    data: bytes
    problems: list[str]
    copies: dict[Path, Path] = field(default_factory=dict)  # source → destination

    @property
    def ok(self) -> bool:
        return not self.problems


def _rebase(file: str, old_base: Path, new_base: Path) -> str:
    target = resolve(old_base, file)
    if Path(file).is_absolute():
        return file
    try:
        return Path(os.path.relpath(target, new_base)).as_posix()
    except ValueError:  # another drive (Windows)
        return str(target)


def rebase_files(project: m.Project, old_base: Path, new_base: Path) -> m.Project:
    """The project with relative file names re-expressed relative to ``new_base``."""
    if Path(old_base).resolve() == Path(new_base).resolve():
        return project
    scene = project.scene
    terrain, texture = scene.terrain, scene.texture
    if isinstance(terrain.source, m.DemTerrain | m.MeshTerrain):
        terrain = dataclasses.replace(terrain, source=dataclasses.replace(
            terrain.source, file=_rebase(terrain.source.file, old_base, new_base)))
    if isinstance(texture.source, m.ImageTexture):
        texture = dataclasses.replace(texture, source=m.ImageTexture(
            _rebase(texture.source.file, old_base, new_base)))
    objects = tuple(dataclasses.replace(o, file=_rebase(o.file, old_base, new_base))
                    for o in scene.objects)
    scene = dataclasses.replace(scene, terrain=terrain, texture=texture, objects=objects)
    return dataclasses.replace(project, scene=scene)


def plan_save(project: m.Project, path: Path, base_dir: Path,
              scratch_files: tuple[str, ...] = ()) -> SavePlan:
    """Check a save of ``project`` (whose files resolve against ``base_dir``) to ``path``.

    ``scratch_files`` are companion files of a new template project, held in
    ``base_dir`` until the first save copies them beside ``path``.
    """
    path = Path(path)
    new_base = path.parent
    copies = {}
    if scratch_files:
        copies = {base_dir / f: new_base / f for f in scratch_files}
        to_write = project
        check_base = base_dir
    else:
        to_write = rebase_files(project, base_dir, new_base)
        check_base = new_base
    data = project_to_bytes(to_write)
    if path.suffix.lower() != ".xml":
        return SavePlan(path, to_write, data, [f"{path}: a project file name must end in .xml"])
    try:
        parsed, smap = parse_project(data, str(path))
    except ProjectError as error:
        return SavePlan(path, to_write, data,
                        [problem_text(p, error.source) for p in error.problems])
    # Relative names like ../x resolve only through an existing folder: make the new
    # folder for the check and take it away again if the save does not happen.
    made = _missing_parents(check_base)
    for folder in reversed(made):
        folder.mkdir()
    try:
        problems = [problem_text(p, str(path))
                    for p in semantic_problems(parsed, check_base, smap)]
    finally:
        for folder in made:
            folder.rmdir()
    for src, dst in copies.items():
        if dst.exists() and dst.read_bytes() != src.read_bytes():
            problems.append(f"{dst}: exists and differs from the template's {src.name}; "
                            "save into another folder")
    return SavePlan(path, to_write, data, problems, copies)


def _missing_parents(folder: Path) -> list[Path]:
    """``folder`` and its ancestors that do not exist, deepest first."""
    out = []
    folder = Path(folder).absolute()
    while not folder.exists():
        out.append(folder)
        folder = folder.parent
    return out


def commit_save(plan: SavePlan) -> None:
    """Write a checked plan: companion files first, the project file last (atomic)."""
    if not plan.ok:
        raise ValueError("refusing to write a project with problems")
    plan.path.parent.mkdir(parents=True, exist_ok=True)
    for src, dst in plan.copies.items():
        if not dst.exists():
            write_bytes_atomic(dst, src.read_bytes())
    write_bytes_atomic(plan.path, plan.data)


def new_from_template(name: str, scratch_root: Path | None = None
                      ) -> tuple[m.Project, Path, tuple[str, ...]]:
    """A template project, the scratch folder holding its companion files, their names."""
    tpl = template(name)
    scratch = Path(tempfile.mkdtemp(prefix=f"designer-{name}-", dir=scratch_root))
    for rel, data in tpl.files.items():
        (scratch / rel).parent.mkdir(parents=True, exist_ok=True)
        (scratch / rel).write_bytes(data)
    return tpl.project, scratch, tuple(tpl.files)


#: words in a problem's message that name the panel whatever its element: the camera's
#: image size times the render's resolution scale is fixed in the Render panel
MESSAGE_KEYWORDS = (
    ("Render", ("resolution-scale", "resolution scale")),
)


def panel_for_problem(line: str) -> str | None:
    """The title of the panel where the problem in ``line`` can be fixed: the one it
    names (``FILE:LINE:COL: Camera › sensor width …``), else the one of its element."""
    for title, _words in PANEL_KEYWORDS:
        if f": {title} › " in line or line.startswith(f"{title} › "):
            return title
    start = line.find("<")
    end = line.find(">", start)
    tag = line[start + 1:end] if start >= 0 else line
    message = line[end + 1:] if start >= 0 else line
    for title, words in MESSAGE_KEYWORDS:
        if any(w in message for w in words):
            return title
    if tag == "image" and any(d.xml in message for d in declared(m.Camera)
                              if d.attr.child == "image"):
        return "Camera"  # the camera's <image> size, not a texture image
    return panel_for_tag(tag)


def blank_project() -> m.Project:
    """A starting point: 100 m × 100 m of flat ground at the origin, grass, a Phantom 4
    Pro camera, no targets and no flight yet."""
    from designer.gui.state.camera_presets import preset

    extent = m.Extent(-50.0, -50.0, 50.0, 50.0)
    scene = m.Scene(
        terrain=m.Terrain(extent, m.FlatTerrain(0.0)),
        texture=m.Texture(m.ProceduralTexture("grass", seed=1, texel_size_m=0.01),
                          repeat_X=5, repeat_Y=5, interpolation="linear"),
        lighting=m.Lighting(m.Sun(azimuth_deg=135.0, elevation_deg=50.0)))
    return m.Project(
        name="New survey", crs="local engineering frame (m)", origin=m.Origin(0.0, 0.0, 0.0),
        scene=scene, cameras=(preset("p4p").camera(),), trajectory=m.Trajectory(),
        render=m.Render(preset="draft", resolution_scale=0.25, workers=1),
        outputs=m.Outputs("output", ("colmap", "opk", "gcp")))  # ODM needs a real CRS
