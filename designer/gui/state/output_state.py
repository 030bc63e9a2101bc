"""Is the render output, and the reconstruction made from it, still the project's?

Qt-free. :func:`render_state` runs ``designer.render.check_output`` (it prepares the
render job in a temporary folder: seconds; call it off the UI thread) and words the
answer for the Render panel (``12 images out of date: the pose``). A reconstruction
records the image digests of the manifest it was made from (``inputs.json`` in its
folder); :func:`reconstruction_state` compares them with the manifest now, and the
processing settings it recorded (its summary.json) with the project's.
"""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from designer.atomic import write_text_atomic
from designer.core.layout import images_dir
from designer.errors import DesignerError
from designer.gui.state.wording import count

RECONSTRUCTION_INPUTS = "inputs.json"
#: how RenderState.text begins when the render folder could not be compared
CANNOT_COMPARE = "cannot compare: "


@dataclass(frozen=True)
class RenderState:
    """The render folder against the project as it is in the window."""

    ok: bool
    n_images: int
    stale: dict[str, list[str]]
    missing: list[str]
    text: str  # one line for the panel ("" when there is nothing rendered to compare)


def stale_text(stale: dict[str, list[str]], missing: list[str], ground_truth: str,
               old_layout: bool = False) -> str:
    """``12 images out of date: the pose; 3 missing``."""
    from designer.render.provenance import describe_parts

    parts = []
    if stale:
        counts = Counter(p for reasons in stale.values() for p in reasons)
        why = ", ".join(f"{describe_parts([p])}" + (f" ({n})" if n != len(stale) else "")
                        for p, n in counts.most_common())
        parts.append(f"{len(stale)} image{'s' if len(stale) != 1 else ''} out of date: {why}")
    if missing:
        parts.append(f"{len(missing)} image{'s' if len(missing) != 1 else ''} not rendered")
    if ground_truth != "up to date":
        parts.append(f"ground truth {ground_truth}")
    if old_layout:
        parts.append("images in the old layout (top of the folder): render again to move "
                     "them into images/ (nothing up to date is rendered again)")
    return "; ".join(parts)


def render_state(out_dir: Path, project_path: Path, project) -> RenderState | None:
    """The render folder's state (None when it holds no render of this project yet)."""
    from designer.render.check_output import check_output
    from designer.render.manifest import MANIFEST

    if not (Path(out_dir) / MANIFEST).is_file():
        return None
    try:
        status = check_output(Path(out_dir), Path(project_path), project=project)
    except DesignerError as error:
        return RenderState(False, 0, {}, [], f"{CANNOT_COMPARE}{error}")
    n = len(status.up_to_date) + len(status.stale) + len(status.missing)
    text = ("up to date" if status.ok else
            stale_text(status.stale, status.missing, status.ground_truth, status.old_layout))
    return RenderState(status.ok, n, dict(status.stale), list(status.missing), text)


def images_stale_text(state: RenderState) -> str:
    """Why a reconstruction is out of date because of the rendered images it was made
    from (a line for the Results panel; "" when they are the project's)."""
    if state.ok:
        return ""
    if state.text.startswith(CANNOT_COMPARE):
        return (f"the rendered images cannot be compared with the project "
                f"({state.text[len(CANNOT_COMPARE):]}); fix the project, render, then "
                "reconstruct again")
    return (f"the rendered images no longer match the project ({state.text}); render, "
            "then reconstruct again")


def manifest_digests(survey_dir: Path) -> dict[str, str]:
    """image name → the digest of the inputs it was rendered from (manifest.json)."""
    from designer.render.manifest import read_manifest

    images = read_manifest(Path(survey_dir)).get("images") or {}
    return {name: str((entry.get("inputs") or {}).get("digest"))
            for name, entry in images.items() if isinstance(entry, dict)}


def record_reconstruction_inputs(survey_dir: Path, recon_dir: Path,
                                 digests: dict[str, str]) -> Path:
    """Write which rendered images (by input digest) a reconstruction was made from."""
    path = Path(recon_dir) / RECONSTRUCTION_INPUTS
    write_text_atomic(path, json.dumps({"survey": str(survey_dir), "images": digests},
                                       indent=1))
    return path


#: the parts of the processing settings, as the Results panel names them
PROCESSING_PARTS = {"calibration": "camera calibration", "gcps": "GCPs",
                    "position_prior": "camera positions", "matching": "matching",
                    "dense": "dense cloud"}


def processing_changes(recon_dir: Path, processing) -> list[str]:
    """The parts of ``processing`` (the project's ``Processing``, None: the defaults)
    that differ from the settings the reconstruction in ``recon_dir`` was made with
    (its summary.json); [] when they agree or were not recorded."""
    from designer.project import model as m
    from designer.sfm.settings import settings_dict

    try:
        used = json.loads((Path(recon_dir) / "summary.json").read_text())["settings"]
    except (OSError, ValueError, KeyError, TypeError):
        return []
    if not isinstance(used, dict):
        return []
    now = json.loads(json.dumps(settings_dict(processing or m.Processing()), default=str))
    changed = []
    for key, value in now.items():
        if key not in used:
            continue
        before = used[key]
        if isinstance(value, dict) and isinstance(before, dict):
            # a setting added since the reconstruction is not a change of it
            differs = any(value.get(k) != before[k] for k in before)
        else:
            differs = value != before
        if differs:
            changed.append(PROCESSING_PARTS.get(key, key.replace("_", " ")))
    return changed


def reconstruction_state(survey_dir: Path, recon_dir: Path, processing=None) -> str:
    """"" when the reconstruction in ``recon_dir`` was made from the images the survey
    holds now and with the project's ``processing`` settings; else why not (a line for
    the Results panel)."""
    images = _images_state(survey_dir, recon_dir)
    changes = processing_changes(recon_dir, processing)
    settings = (f"the processing settings changed since this reconstruction "
                f"({', '.join(changes)})" if changes else "")
    if images and settings:
        return f"{images}, and {settings}: reconstruct again"
    if settings:
        return f"{settings}: reconstruct again"
    return f"{images}: reconstruct again" if images else ""


def _images_state(survey_dir: Path, recon_dir: Path) -> str:
    """Why the survey's images are not those the reconstruction was made from ("")."""
    now = manifest_digests(survey_dir)
    record = Path(recon_dir) / RECONSTRUCTION_INPUTS
    try:
        used = json.loads(record.read_text())["images"]
    except (OSError, ValueError, KeyError, TypeError):
        summary = Path(recon_dir) / "summary.json"
        images = [images_dir(Path(survey_dir)) / name for name in now]
        if not summary.is_file():
            return ""
        newer = [p for p in images if p.is_file()
                 and p.stat().st_mtime > summary.stat().st_mtime]
        return (f"{count(len(newer), 'image')} "
                f"{'was' if len(newer) == 1 else 'were'} rendered after this reconstruction"
                if newer else "")
    changed = sorted(n for n in set(now) | set(used) if now.get(n) != used.get(n))
    if not changed:
        return ""
    return (f"{len(changed)} image{'s' if len(changed) != 1 else ''} rendered anew since "
            "this reconstruction")
