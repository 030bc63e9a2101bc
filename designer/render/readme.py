"""OUT/README.txt: which file of a render output folder each program takes.

Generated from what was actually written — the image names and the ground-truth files
:func:`designer.export.dispatch.write_all` returned — so it never names a file the
folder does not have. Paths are relative to the output folder.

OpenDroneMap's project layout (ODM ``opendm/types.py`` ``ODM_Tree``; docs "Image
Geolocation Files" and "Ground Control Points"): a project folder holds ``images/``, and
``gcp_list.txt`` / ``geo.txt`` are looked for only in the project folder itself (its
top level, not inside ``images/``) unless ``--gcp`` / ``--geo`` name them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from designer import __version__
from designer.atomic import write_text_atomic
from designer.core.layout import GROUND_TRUTH_DIR, IMAGES_DIR, JOB_DIR, MANIFEST, README


def readme_text(out_dir: Path, image_names: Sequence[str], ground_truth: Mapping[str, Path],
                *, project: str = "", image_size_px: tuple[int, int] | None = None,
                camera_sizes_px: Mapping[str, tuple[int, int]] | None = None,
                readout_s: float | None = None) -> str:
    """The README of ``out_dir`` whose images are ``image_names`` and whose ground truth
    is ``ground_truth`` ({write_all key: path}); ``camera_sizes_px`` the image size of
    each camera of a multi-camera rig (instead of ``image_size_px``); ``readout_s`` the
    rolling-shutter readout of the camera (None: a global shutter)."""
    out_dir = Path(out_dir)

    def rel(key: str) -> str | None:
        path = ground_truth.get(key)
        if path is None:
            return None
        path = Path(path)
        try:
            path = path.relative_to(out_dir)
        except ValueError:
            pass
        return path.as_posix() + ("/" if key == "colmap" else "")

    names = sorted(image_names)
    suffixes = sorted({Path(n).suffix.lower().lstrip(".").upper() for n in names})
    size = f", {image_size_px[0]} x {image_size_px[1]} px" if image_size_px else ""
    if camera_sizes_px:
        size = f", {len(camera_sizes_px)} cameras (" + ", ".join(
            f"{c} {w} x {h} px" for c, (w, h) in camera_sizes_px.items()) + ")"
    span = f" ({names[0]} … {names[-1]})" if len(names) > 1 else (
        f" ({names[0]})" if names else "")
    lines = [
        f"Survey images and ground truth written by designer {__version__}"
        + (f" from the project {project}" if project else "") + ".",
        "All paths below are relative to this folder.",
        "",
        f"{IMAGES_DIR}/          {len(names)} images{span}, {'/'.join(suffixes) or 'none'}"
        f"{size}; nothing else is ever written in this folder",
        f"{GROUND_TRUTH_DIR}/    the true camera poses, camera and GCPs (files below)",
        f"{MANIFEST}    versions, render settings, per-image inputs and render seconds",
        f"{JOB_DIR}/   designer's working files (scene, logs); no other program needs them",
        "",
    ]
    used: set[str] = set()

    def section(title: str, rows: list[tuple[str, str | None]], notes: Sequence[str] = (),
                images: str | None = None):
        """The program's lines, when at least one of its ground-truth files was written."""
        present = [(what, path) for what, path in rows if path]
        if not present:
            return
        lines.append(title)
        if images:
            present.insert(0, ("images", images))
        lines.extend(f"  {what + ':':<22}{path}" for what, path in present)
        lines.extend(f"  {note}" for note in notes)
        lines.append("")

    colmap = rel("colmap")
    database, pairs = rel("colmap_database"), rel("colmap_pairs")
    steps = []
    if colmap and database and pairs:
        steps = [
            "Headless, with COLMAP's default settings (run in this folder; the copy keeps",
            "the ground truth as written; the database holds the cameras and images with",
            "the model's IDs, the pairs are the images whose footprints overlap):",
            *(f"    {line}" for line in colmap_commands(database, pairs, colmap)),
            "  then, where COLMAP has CUDA (dense stereo needs it):",
            "    colmap patch_match_stereo --workspace_path dense",
            "    colmap stereo_fusion --workspace_path dense --output_path dense/fused.ply",
            "Coordinates are local (world = model + the offset in offset.json), so COLMAP's",
            "float32 PLY keeps them to 0.1 mm. designer compare reads the offset from a",
            "model folder; give it a PLY with --offset E N H (the numbers in offset.json).",
        ]
    section("COLMAP", [("true model", colmap), ("database (IDs)", database),
                       ("image pairs", pairs)], steps,
            images=f"--image_path {IMAGES_DIR}")
    used |= {"colmap_database", "colmap_pairs"}
    used |= {"colmap", "colmap_cameras", "colmap_images", "colmap_points3D"}
    gcp_list, geo = rel("odm_gcp_list"), rel("odm_geo")
    section("OpenDroneMap", [("GCP image points", gcp_list), ("image positions", geo),
                             ("camera models", rel("odm_cameras"))],
            ["ODM reads a project folder PROJECT with the images in PROJECT/images/ and",
             "gcp_list.txt and geo.txt in PROJECT itself (beside images/, not inside it);",
             "copy them there, or pass --gcp and --geo with the paths above. WebODM: upload",
             "them together with the images."], images=f"{IMAGES_DIR}/")
    used |= {"odm_gcp_list", "odm_geo", "odm_cameras"}
    per_camera = sorted(k for k in ground_truth if k.startswith("metashape_calibration_"))
    used |= set(per_camera)
    section("Agisoft Metashape",
            [("camera calibration", rel("metashape_calibration")),
             *((f"calibration {k.removeprefix('metashape_calibration_')}", rel(k))
               for k in per_camera),
             ("camera reference", rel("metashape_cameras")),
             ("markers reference", rel("metashape_markers"))],
            ["Calibration: Tools > Camera Calibration > Load. References: Reference pane >",
             "Import Reference; set the rotation angles to Omega, Phi, Kappa."],
            images=f"Add Photos from {IMAGES_DIR}/")
    used |= {"metashape_calibration", "metashape_cameras", "metashape_markers"}
    section("Tables (any program; '#' lines describe the columns)",
            [("camera poses (OPK)", rel("opk")), ("GCP coordinates", rel("gcp_truth")),
             ("GCP image points", rel("gcp_observations"))])
    used |= {"opk", "gcp_truth", "gcp_observations"}
    if readout_s:
        section("Rolling shutter (the images' rows are read over "
                f"{readout_s * 1000:g} ms, the camera moving)",
                [("readout and velocity", rel("rolling_shutter"))],
                [f"ODM: --rolling-shutter --rolling-shutter-readout {readout_s * 1000:g}",
                 "Metashape: Camera Calibration > Rolling shutter compensation; Pix4D: the",
                 "linear rolling shutter model. Poses everywhere are those of the first row",
                 "read; GCP image points are where the rolling-shutter images show them."])
        used.add("rolling_shutter")
    others = [(key, rel(key)) for key in sorted(ground_truth) if key not in used]
    section("Other ground-truth files", others)
    lines += [
        "designer",
        "  designer reconstruct OUT             reads images/ and ground-truth/colmap/",
        "  designer compare CLOUD PROJECT.xml -o DIR   a cloud against the true surface",
        "  designer check-output OUT            are the images still the project's?",
        "  (OUT is this folder, PROJECT.xml the project it was rendered from)",
        "",
    ]
    return "\n".join(lines)


def colmap_commands(database: str, pairs: str, model: str) -> list[str]:
    """The command-line steps of README.txt from the images to a triangulated model with
    the true poses and its undistorted images (COLMAP 3.8's command line, CPU only)."""
    model = model.rstrip("/")
    return [
        f"cp {database} colmap.db",
        f"colmap feature_extractor --database_path colmap.db --image_path {IMAGES_DIR}"
        " --SiftExtraction.use_gpu 0",
        f"colmap matches_importer --database_path colmap.db --match_list_path {pairs}"
        " --match_type pairs --SiftMatching.use_gpu 0",
        "mkdir -p triangulated",
        f"colmap point_triangulator --database_path colmap.db --image_path {IMAGES_DIR}"
        f" --input_path {model} --output_path triangulated"
        " --Mapper.ba_refine_focal_length 0 --Mapper.ba_refine_principal_point 0"
        " --Mapper.ba_refine_extra_params 0",
        f"colmap image_undistorter --image_path {IMAGES_DIR} --input_path triangulated"
        " --output_path dense --output_type COLMAP",
    ]


def write_readme(out_dir: Path, image_names: Sequence[str], ground_truth: Mapping[str, Path],
                 **kwargs) -> Path:
    """Write OUT/README.txt atomically (see :func:`readme_text`); returns its path."""
    path = Path(out_dir) / README
    write_text_atomic(path, readme_text(out_dir, image_names, ground_truth, **kwargs))
    return path
