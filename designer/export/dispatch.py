"""Write every requested ground-truth format of a survey into one folder.

Layout under ``out_dir`` (keys of the returned dict in brackets):

* ``colmap/`` cameras.txt, images.txt, points3D.txt, offset.json, database.db  [colmap,
  colmap_cameras, colmap_images, colmap_points3D, colmap_offset, colmap_database; the
  database holds the cameras and images with the model's IDs,
  :mod:`designer.export.colmap_db`] — world coordinates
  minus the offset ``colmap_offset`` chooses (default ``local``: the mean camera centre
  rounded to metres; see :func:`designer.export.colmap.colmap_offset_world`), which
  offset.json names;
* ``odm/gcp_list.txt``, ``odm/geo.txt``  [odm_gcp_list, odm_geo] — control GCPs only
  unless ``odm_gcp_roles`` says otherwise;
* ``metashape/calibration.xml``, ``metashape/cameras_reference.csv``,
  ``metashape/markers_reference.csv``, ``metashape/markers.xml``  [metashape_calibration,
  metashape_cameras, metashape_markers, metashape_markers_xml] — the XML carries the
  marker projections and control (enabled) / check (disabled) flags;
* ``odm/cameras.json`` [odm_cameras] — a multi-camera rig's cameras only;
* a multi-camera rig (``interior`` a :class:`~designer.core.truth.CameraSet`): COLMAP
  one camera per physical camera, Metashape one sensor per camera (and
  ``metashape/calibration_<CAMERA>.xml`` each) [metashape_calibration_<CAMERA>], and a
  ``camera`` column in ``camera_poses_opk.csv`` and ``gcp_observations.csv``;
* ``camera_poses_opk.csv``  [opk];
* ``gcp_truth.csv``, ``gcp_observations.csv``  [gcp_truth, gcp_observations];
* ``image_times.csv`` [image_times] and a ``time`` column in ``camera_poses_opk.csv`` —
  only when the photos have times (a project with a time line, docs/world.md).

Pixel origins, rotation conventions, units and coefficient swaps are documented in
each format's module. All file contents are produced (and every input checked)
before the first file is written, so bad input leaves nothing behind; each file is
then written atomically.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from designer.core.interior import InteriorOrientation
from designer.core.truth import (
    CameraPose,
    CameraSet,
    GcpObservation,
    GroundControlPoint,
    ImageTime,
)
from designer.export import colmap, metashape, odm, tables
from designer.export._text import ExportError, check_crs, check_unique, write_texts

FORMATS = ("colmap", "odm", "metashape", "opk", "gcp")


def write_all(
    out_dir: str | os.PathLike,
    interior: InteriorOrientation | CameraSet,
    poses: Sequence[CameraPose],
    gcps: Sequence[GroundControlPoint],
    observations: Sequence[GcpObservation],
    crs: str,
    formats: Sequence[str] = FORMATS,
    *,
    colmap_offset="local",
    odm_gcp_roles: Sequence[str] = ("control",),
    image_times: Sequence[ImageTime] | None = None,
) -> dict[str, Path]:
    """Write the chosen ``formats`` (subset of FORMATS) under ``out_dir``; {key: path}.

    ``colmap_offset``: ``"local"``, ``"none"``, three numbers or ``"E,N,H"`` (metres).
    ``interior``: the one camera, or a rig's :class:`CameraSet` (every image's camera).
    """
    unknown = [f for f in formats if f not in FORMATS]
    if unknown:
        raise ExportError(f"unknown export format(s) {unknown}; choose from {list(FORMATS)}")
    crs = check_crs(crs)
    check_unique((p.image_name for p in poses), "image name")
    check_unique((g.gcp_id for g in gcps), "GCP id")
    images = {p.image_name for p in poses}
    cameras = interior if isinstance(interior, CameraSet) else None
    if cameras is not None:
        cameras.covers(images)
    ids = {g.gcp_id for g in gcps}
    for o in observations:
        if o.image_name not in images:
            raise ExportError(f"observation of {o.gcp_id!r} in unknown image {o.image_name!r}")
        if o.gcp_id not in ids:
            raise ExportError(f"observation of unknown GCP {o.gcp_id!r} in {o.image_name!r}")

    out = Path(out_dir)
    texts: dict[Path, str] = {}
    paths: dict[str, Path] = {}

    def add(key: str, path: Path, text: str) -> None:
        texts[path] = text
        paths[key] = path

    if "colmap" in formats:
        folder = out / "colmap"
        offset = colmap.colmap_offset_world(colmap_offset, poses)
        texts_ = colmap.colmap_texts(folder, interior, poses, offset,
                                     colmap.offset_choice_name(colmap_offset), crs)
        for path, text in texts_.items():
            add(f"colmap_{path.stem}", path, text)
        paths["colmap"] = folder
    if "odm" in formats:
        add("odm_gcp_list", out / "odm" / "gcp_list.txt",
            odm.odm_gcp_list_text(gcps, observations, crs, odm_gcp_roles))
        add("odm_geo", out / "odm" / "geo.txt", odm.odm_geo_text(poses, crs))
        if cameras is not None:
            add("odm_cameras", out / "odm" / "cameras.json", odm.odm_cameras_json(cameras))
    if "metashape" in formats:
        folder = out / "metashape"
        if cameras is None:
            add("metashape_calibration", folder / "calibration.xml",
                metashape.metashape_calibration_xml(interior))
        else:
            for camera_id, camera in cameras.interiors.items():
                add(f"metashape_calibration_{camera_id}",
                    folder / f"calibration_{camera_id}.xml",
                    metashape.metashape_calibration_xml(camera))
        add("metashape_cameras", folder / "cameras_reference.csv",
            metashape.metashape_cameras_csv(poses, crs))
        add("metashape_markers", folder / "markers_reference.csv",
            metashape.metashape_markers_csv(gcps, crs))
        add("metashape_markers_xml", folder / "markers.xml",
            metashape.metashape_markers_xml(poses, gcps, observations, crs, cameras,
                                            interior=interior if cameras is None else None))
    if "opk" in formats:
        add("opk", out / "camera_poses_opk.csv",
            tables.opk_csv(poses, crs, image_times, cameras))
    if "gcp" in formats:
        add("gcp_truth", out / "gcp_truth.csv", tables.gcp_truth_csv(gcps, crs))
        add("gcp_observations", out / "gcp_observations.csv",
            tables.gcp_observations_csv(observations, cameras))
    if image_times is not None:
        add("image_times", out / "image_times.csv", tables.image_times_csv(image_times))
    write_texts(texts)
    if "colmap" in formats:  # the cameras and images with their IDs, for COLMAP's tools
        from designer.export.colmap_db import write_colmap_database

        paths["colmap_database"] = write_colmap_database(out / "colmap" / "database.db",
                                                         interior, poses)
    return paths
