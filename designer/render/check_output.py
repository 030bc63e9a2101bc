"""Does an output folder still belong to its project? Images and ground truth, checked.

:func:`check_output` prepares the project's render job in a temporary folder (the output
folder is only read), computes what every image and the ground truth would be made from
now, and compares that with the manifest's record and with the files present.
"""

from __future__ import annotations

import tempfile
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from designer.core.layout import (
    GROUND_TRUTH_DIR,
    IMAGES_DIR,
    MANIFEST,
    images_dir,
    is_image_file,
    uses_old_layout,
)
from designer.errors import DesignerError
from designer.render.manifest import read_manifest
from designer.render.provenance import (
    describe_parts,
    ground_truth_digest,
    job_provenance,
    size_reason,
)


@dataclass(frozen=True)
class OutputStatus:
    """The state of an output folder against its project."""

    out_dir: Path
    project: Path
    up_to_date: list[str] = field(default_factory=list)
    stale: dict[str, list[str]] = field(default_factory=dict)  # image → changed parts
    missing: list[str] = field(default_factory=list)
    extra: list[str] = field(default_factory=list)  # image files the project does not make
    ground_truth: str = "up to date"  # or "missing", "out of date", "edited"
    #: the images are at the folder's top level (written before images/ existed)
    old_layout: bool = False

    @property
    def ok(self) -> bool:
        return (not self.stale and not self.missing and not self.extra
                and self.ground_truth == "up to date" and not self.old_layout)

    def summary(self) -> str:
        n = len(self.up_to_date) + len(self.stale) + len(self.missing)
        lines = [f"{self.out_dir}: {len(self.up_to_date)} of {n} images up to date with "
                 f"{self.project}"]
        if self.stale:
            lines.append(f"  {len(self.stale)} out of date: {count_reasons(self.stale)}")
        if self.missing:
            lines.append(f"  {len(self.missing)} missing: {', '.join(self.missing[:5])}"
                         + (" …" if len(self.missing) > 5 else ""))
        if self.extra:
            lines.append(f"  {len(self.extra)} image files not made by this project: "
                         f"{', '.join(self.extra[:5])}" + (" …" if len(self.extra) > 5 else ""))
        lines.append(f"  ground truth: {self.ground_truth}")
        if self.old_layout:
            lines.append(f"  old layout: the images are at the top of {self.out_dir}, not in "
                         f"{IMAGES_DIR}/ (programs that read a whole folder also see the "
                         "ground truth and working files there); a render with --resume "
                         f"moves them into {IMAGES_DIR}/ and renders only what is missing")
        if not self.ok:
            lines.append(f"  fix: designer render {self.project} -o {self.out_dir} --resume "
                         "(re-renders only what changed and rewrites the ground truth)"
                         + (f", moving the images into {IMAGES_DIR}/" if self.old_layout else ""))
        return "\n".join(lines)

    def to_json(self) -> dict:
        return {"out_dir": str(self.out_dir), "project": str(self.project), "ok": self.ok,
                "up_to_date": self.up_to_date, "stale": self.stale,
                "missing": self.missing, "extra": self.extra,
                "ground_truth": self.ground_truth, "old_layout": self.old_layout,
                "images_dir": str(images_dir(self.out_dir))}


def count_reasons(stale: dict) -> str:
    """'{img: [pose], img2: [pose, targets]}' → '2 by the pose, 1 by the GCP targets in view'."""
    counts = Counter(p for parts in stale.values() for p in parts)
    return "; ".join(f"{n} by {describe_parts([p])}" for p, n in counts.most_common())


def check_output(out_dir: Path, project_path: Path | None = None, *,
                 project=None) -> OutputStatus:
    """Compare the images and ground truth in ``out_dir`` with what its project makes now.

    The project is read from ``project_path`` (default: the one the manifest names), or
    given as a model in ``project`` (as the desktop designer holds it; its files are then
    found next to ``project_path``).
    """
    from designer.project import load_project
    from designer.render.job import prepare_job
    from designer.render.pipeline import write_ground_truth
    from designer.render.runner import image_size_px

    out_dir = Path(out_dir)
    manifest = read_manifest(out_dir)
    if not manifest:
        raise DesignerError(f"{out_dir / MANIFEST}: no readable manifest; is {out_dir} an "
                            "output folder of 'designer render'?")
    if project_path is None and project is None:
        recorded = manifest.get("project")
        if not recorded or not Path(recorded).is_file():
            raise DesignerError(f"{out_dir / MANIFEST}: the project it was rendered from "
                                f"({recorded}) is not there; give it with --project")
        project_path = Path(recorded)
    if project_path is None:
        project_path = Path(manifest.get("project") or out_dir / "project.xml")
    if project is None:
        project = load_project(project_path)
    quality = (manifest.get("render") or {}).get("quality")
    with tempfile.TemporaryDirectory(prefix="designer-check-") as tmp:
        scratch = Path(tmp)
        prepared = prepare_job(project, Path(project_path).parent, scratch, quality)
        provenance = job_provenance(prepared.job, prepared.job_path.parent, project)
        offset = (manifest.get("ground_truth") or {}).get("colmap_offset") or "local"
        write_ground_truth(project, prepared, scratch, str(offset))
        truth_now = ground_truth_digest(scratch / GROUND_TRUTH_DIR)
    job = prepared.job
    images = manifest.get("images", {}) if isinstance(manifest.get("images"), dict) else {}
    status = OutputStatus(out_dir=out_dir, project=Path(project_path),
                          old_layout=uses_old_layout(out_dir))
    folder = images_dir(out_dir)
    for index, name in sorted(job.image_names.items()):
        path = folder / name
        size_px = image_size_px(path)
        if size_px is None:  # not there, or not readable
            status.missing.append(name)
            continue
        inputs = (images.get(name) or {}).get("inputs")
        if (inputs and inputs.get("digest") == provenance[index].digest
                and size_px == tuple(job.frame_size_px(index))):
            status.up_to_date.append(name)
        else:
            status.stale[name] = provenance[index].changed_parts(inputs, size_px) or [
                size_reason(size_px, job.frame_size_px(index))]
    names = set(job.image_names.values())
    if folder.is_dir():
        status.extra.extend(sorted(p.name for p in folder.iterdir()
                                   if is_image_file(p) and p.name not in names))
    folder = out_dir / GROUND_TRUTH_DIR
    if not folder.is_dir():
        truth = "missing"
    elif ground_truth_digest(folder) != truth_now:
        recorded_truth = (manifest.get("ground_truth") or {}).get("digest")
        truth = ("edited after rendering" if recorded_truth == truth_now
                 else "out of date (the project changed since it was written)")
    else:
        truth = "up to date"
    return OutputStatus(**{**status.__dict__, "ground_truth": truth})
