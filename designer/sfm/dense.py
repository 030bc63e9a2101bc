"""Dense point cloud on the CPU: semi-global matching depth maps fused by COLMAP.

Stages (each timed in :attr:`DenseCloud.stage_seconds`):

1. ``undistort`` — ``pycolmap.undistort_images`` writes COLMAP's dense workspace
   (``images/``, ``sparse/``, ``stereo/``) with pinhole cameras; with
   ``max_image_size_px`` the images and cameras are then scaled down (area averaging).
2. ``pairs`` — each image gets up to two source images among those sharing sparse
   points with it, preferring wide baselines and different epipolar directions
   (:func:`designer.sfm.stereo_pairs.choose_pairs`).
3. ``depth_maps`` — every pair is rectified with the known poses and matched with
   OpenCV's semi-global matcher (``StereoSGBM``); the disparity search range comes from
   the sparse points the image sees. The pair depths are combined per pixel, normals are
   taken from the depth map, and both are written as COLMAP ``*.geometric.bin`` maps.
4. ``fusion`` — ``pycolmap.stereo_fusion`` (COLMAP's geometric-consistency fusion, CPU):
   a pixel becomes a point only when the depth maps of at least
   ``FUSION_MIN_PIXELS`` − 1 other images agree with it.

COLMAP's own PatchMatch stereo would replace stage 3 but needs CUDA; it is not used.

Numerical care: the sparse model is in a LOCAL frame (world − ``origin_world``);
COLMAP's dense workspace (depth maps, fused points) is float32, so it only ever sees
local coordinates. The origin is added back in float64 at the end.

Resuming: a run writes ``dense.json`` (its settings and a digest of the sparse model);
a rerun with the same settings reuses the undistorted workspace and every depth map
already written (each is written atomically).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path, write_text_atomic
from designer.errors import DesignerError

MATCHER = "opencv-sgbm + colmap stereo_fusion"
#: pixels (images) a fused point needs, itself included (COLMAP's default: 5)
FUSION_MIN_PIXELS = 3
#: largest angle (deg) between the normals of pixels fused into one point
FUSION_MAX_NORMAL_ERROR_DEG = 30.0
#: source images per reference image
N_NEIGHBOURS = 2
#: the farthest (m) a camera of the local model may be from its origin: float32 (COLMAP's
#: dense workspace) resolves 2 mm there
MAX_LOCAL_DISTANCE_M = 2.0e4
#: COLMAP's fusion on several threads claims pixels in an order that depends on thread
#: timing, so the cloud differs from run to run (by ~1 % of its points); one thread
#: makes it repeatable bit for bit
FUSION_THREADS = 1


@dataclass(frozen=True, eq=False)
class DenseCloud:
    """Fused points: ``points_world`` (N, 3) float64 metres in the world frame,
    ``colors_rgb`` (N, 3) uint8, the ``matcher`` used and seconds per stage."""

    points_world: np.ndarray
    colors_rgb: np.ndarray
    matcher: str = MATCHER
    stage_seconds: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.points_world)


def dense_cloud(image_dir: Path, sparse_model_dir: Path, work_dir: Path, *,
                origin_world: np.ndarray, max_image_size_px: int | None = None,
                log: Callable[[str], None] = print,
                bounds_world: tuple[np.ndarray, np.ndarray] | None = None,
                cancel: Callable[[], bool] | None = None,
                threads: int = 2) -> DenseCloud:
    """Depth maps and fusion for the images of a sparse model (local frame).

    ``image_dir`` holds the images named in ``sparse_model_dir`` (a COLMAP model in
    local coordinates: world − ``origin_world`` (3,)); ``work_dir`` receives the dense
    workspace. ``max_image_size_px`` limits the longer image side used for matching.
    ``bounds_world`` ((3,) min, (3,) max corner, world metres) keeps only fused points
    inside that box — the area of interest, e.g. the modelled scene. ``cancel`` is
    polled between images; when it returns True the run stops with a
    :class:`DesignerError` and a rerun resumes. ``threads`` depth maps are computed at
    a time. Raises :class:`DesignerError` when no image pair overlaps or fusion yields
    no point. ``stage_seconds`` holds wall-clock (``*_s``) and this process's CPU
    (``*_cpu_s``) seconds per stage.
    """
    import pycolmap

    image_dir, sparse_model_dir, work = Path(image_dir), Path(sparse_model_dir), Path(work_dir)
    origin = np.asarray(origin_world, dtype=np.float64).reshape(3)
    _check_inputs(pycolmap, image_dir, sparse_model_dir)
    seconds: dict[str, float] = {}
    ws = work / "workspace"
    with _stage(seconds, "undistort"):
        _undistorted_workspace(pycolmap, image_dir, sparse_model_dir, work, max_image_size_px,
                               log)

    with _stage(seconds, "pairs"):
        rec = pycolmap.Reconstruction(str(ws / "sparse"))
        views, point_ids, xyz_by_id = _views(rec)
        pairs = _choose(views, point_ids, xyz_by_id)
    n_pairs = sum(len(p) for p in pairs)
    if n_pairs == 0:
        raise DesignerError(
            f"{sparse_model_dir}: no two images share enough sparse points for dense "
            "matching; give overlapping images (a survey with front and side overlap)")
    log(f"dense: {n_pairs} stereo pairs for {len(views)} images")

    with _stage(seconds, "depth_maps"):
        _depth_maps(ws, views, pairs, point_ids, xyz_by_id, log, cancel, threads)

    with _stage(seconds, "fusion"):
        xyz_local, rgb = _fuse(pycolmap, work, views, origin, bounds_world, log)
    _check_fused(xyz_local, work, bounds_world)
    log(f"dense: {len(xyz_local)} points")
    points_world = xyz_local.astype(np.float64) + origin
    return DenseCloud(points_world, rgb, MATCHER, seconds)


def _undistorted_workspace(pycolmap, image_dir: Path, sparse_model_dir: Path, work: Path,
                           max_image_size_px: int | None, log: Callable[[str], None]) -> None:
    """``work/workspace``: the images undistorted for the model (COLMAP's dense
    workspace), kept when ``work/dense.json`` says it was made with the same settings
    and model (a rerun resumes in it), else made anew."""
    ws = work / "workspace"
    settings = {"version": 2, "max_image_size_px": max_image_size_px,
                "n_neighbours": N_NEIGHBOURS, "model": _model_digest(sparse_model_dir)}
    stamp = work / "dense.json"
    resume = stamp.is_file() and json.loads(stamp.read_text()) == settings \
        and (ws / "sparse").is_dir()
    if resume:
        log("dense: resuming in the existing workspace")
        return
    stamp.unlink(missing_ok=True)
    if ws.exists():
        shutil.rmtree(ws)
    work.mkdir(parents=True, exist_ok=True)
    log("dense: undistorting images")
    undistort = pycolmap.UndistortCameraOptions()
    if max_image_size_px:
        undistort.max_image_size = int(max_image_size_px)
    pycolmap.undistort_images(ws, sparse_model_dir, image_dir, output_type="COLMAP",
                              undistort_options=undistort)
    write_text_atomic(stamp, json.dumps(settings, indent=1))


def _fuse(pycolmap, work: Path, views, origin: np.ndarray, bounds_world,
          log: Callable[[str], None]) -> tuple[np.ndarray, np.ndarray]:
    """The depth maps of ``work/workspace`` fused (COLMAP stereo_fusion) into points
    (local frame, m) and their colours, inside ``bounds_world`` (world) when given."""
    ws = work / "workspace"
    _write_fusion_config(ws, views)
    options = pycolmap.StereoFusionOptions()
    options.min_num_pixels = FUSION_MIN_PIXELS
    options.max_normal_error = FUSION_MAX_NORMAL_ERROR_DEG
    options.num_threads = FUSION_THREADS
    if bounds_world is not None:
        lo, hi = (np.asarray(b, dtype=np.float64).reshape(3) - origin
                  for b in bounds_world)
        options.bounding_box = (lo.astype(np.float32), hi.astype(np.float32))
    fused = work / "fused.ply"
    fused.unlink(missing_ok=True)
    log("dense: fusing depth maps (COLMAP stereo_fusion)")
    pycolmap.stereo_fusion(fused, ws, input_type="geometric", options=options,
                           output_type="PLY")
    return _read_fused_ply(fused)


def _check_fused(xyz_local: np.ndarray, work: Path, bounds_world) -> None:
    """A fusion that kept no point is a clear error, naming the box when there is one."""
    if len(xyz_local) == 0 and bounds_world is not None:
        lo, hi = (np.asarray(b, dtype=np.float64).reshape(3) for b in bounds_world)
        raise DesignerError(
            f"{work}: fusion kept no point inside the area-of-interest box {lo.tolist()} - "
            f"{hi.tolist()}; give the box in world coordinates around the surveyed area")
    if len(xyz_local) == 0:
        raise DesignerError(
            f"{work}: fusion kept no point: the depth maps of different images do not "
            f"agree (each point needs {FUSION_MIN_PIXELS} overlapping images with texture)")


def _check_inputs(pycolmap, image_dir: Path, model_dir: Path) -> None:
    """Clear errors for a missing folder, a folder without a model, and a model in world
    (UTM-sized) coordinates, before anything is written."""
    if not image_dir.is_dir():
        raise DesignerError(f"{image_dir}: no such image folder; give the folder holding "
                            "the images the sparse model names")
    if not any((model_dir / f"{f}.{e}").is_file() for f in ("cameras", "images")
               for e in ("bin", "txt")):
        raise DesignerError(f"{model_dir}: no COLMAP model (cameras/images .bin or .txt); "
                            "give the sparse model folder")
    rec = pycolmap.Reconstruction(str(model_dir))
    C = np.array([img.projection_center() for img in rec.images.values() if img.has_pose])
    if len(C) == 0:
        raise DesignerError(f"{model_dir}: the model has no registered image")
    far = float(np.abs(C).max())
    if far > MAX_LOCAL_DISTANCE_M:
        raise DesignerError(
            f"{model_dir}: cameras lie up to {far:.0f} m from the model's origin: it is in "
            "world coordinates, which COLMAP's float32 dense workspace cannot hold to the "
            "millimetre; write it in a local frame with write_local_model() and pass that "
            "origin")


@contextlib.contextmanager
def _stage(seconds: dict, name: str):
    wall, cpu = time.perf_counter(), time.process_time()
    try:
        yield
    finally:
        seconds[f"{name}_s"] = time.perf_counter() - wall
        seconds[f"{name}_cpu_s"] = time.process_time() - cpu


def _depth_maps(ws: Path, views, pairs, point_ids, xyz_by_id, log, cancel, threads) -> None:
    """Compute and write every missing depth and normal map, ``threads`` at a time
    (OpenCV and numpy release the interpreter lock in their heavy parts)."""
    from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

    depth_dir, normal_dir = ws / "stereo" / "depth_maps", ws / "stereo" / "normal_maps"
    depth_dir.mkdir(parents=True, exist_ok=True)
    normal_dir.mkdir(parents=True, exist_ok=True)
    todo = [i for i, v in enumerate(views)
            if not ((depth_dir / f"{v.name}.geometric.bin").is_file()
                    and (normal_dir / f"{v.name}.geometric.bin").is_file())]
    done = len(views) - len(todo)
    with ThreadPoolExecutor(max_workers=max(1, int(threads))) as pool:
        running = set()
        queue = list(todo)
        while queue or running:
            while queue and len(running) < max(1, int(threads)):
                if cancel is not None and cancel():
                    for f in running:
                        f.cancel()
                    wait(running)
                    raise DesignerError(f"{ws.parent}: dense matching cancelled; run again "
                                        "to resume")
                i = queue.pop(0)
                running.add(pool.submit(_one_depth_map, ws, views, i, pairs[i],
                                        point_ids[i], xyz_by_id))
            finished, running = wait(running, return_when=FIRST_COMPLETED)
            for f in finished:
                name, n_pixels = f.result()
                done += 1
                log(f"dense: depth map {done}/{len(views)} {name}: {n_pixels} pixels")


def _one_depth_map(ws: Path, views, i: int, sources: list[int], ids, xyz_by_id):
    import cv2

    from designer.sfm.depth_maps import normals_from_depth, write_colmap_array
    from designer.sfm.stereo_pairs import combine_depths, disparity_range, rectify, sgbm_depth

    view = views[i]

    def gray(v):
        img = cv2.imread(str(ws / "images" / v.name), cv2.IMREAD_GRAYSCALE)
        if img is None:
            raise DesignerError(f"{ws / 'images' / v.name}: cannot read the undistorted image")
        return img

    seen = np.array([xyz_by_id[p] for p in ids]).reshape(-1, 3)
    depths = []
    ref_gray = None
    for j in sources:
        pair = rectify(view, views[j])
        rng = None if pair is None else disparity_range(pair, seen, view)
        if rng is not None:
            ref_gray = gray(view) if ref_gray is None else ref_gray
            depths.append(sgbm_depth(ref_gray, gray(views[j]), view, views[j], pair, rng))
    depth = combine_depths(depths) if depths else \
        np.zeros((view.height_px, view.width_px), np.float32)
    write_colmap_array(ws / "stereo" / "normal_maps" / f"{view.name}.geometric.bin",
                       normals_from_depth(depth, view.K))
    write_colmap_array(ws / "stereo" / "depth_maps" / f"{view.name}.geometric.bin", depth)
    return view.name, int(np.count_nonzero(depth))


def write_local_model(model_dir: Path, out_dir: Path,
                      origin_world: np.ndarray | None = None) -> np.ndarray:
    """Write the COLMAP model in ``model_dir`` (world coordinates) shifted into a local
    frame (world − origin) to ``out_dir`` and return the origin (3,) float64: the given
    one, or the rounded mean of the camera centres. The shift is exact in float64."""
    import pycolmap

    rec = pycolmap.Reconstruction(str(model_dir))
    if origin_world is None:
        origin_world = np.round(np.mean([img.projection_center()
                                         for img in rec.images.values()], axis=0))
    origin = np.asarray(origin_world, dtype=np.float64).reshape(3)
    rec.transform(pycolmap.Sim3d(1.0, pycolmap.Rotation3d(), -origin))
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    rec.write(str(out_dir))
    return origin


def _model_digest(model_dir: Path) -> str:
    h = hashlib.sha1()
    for p in sorted(Path(model_dir).glob("*")):
        if p.suffix in (".bin", ".txt"):
            h.update(p.name.encode())
            h.update(p.read_bytes())
    return h.hexdigest()


def _views(rec):
    """Views in image order, each view's observed point ids, and point coordinates."""
    from designer.sfm.stereo_pairs import View

    views, point_ids = [], []
    for image_id in sorted(rec.reg_image_ids()):
        image = rec.images[image_id]
        cam = rec.cameras[image.camera_id]
        pose = image.cam_from_world()
        M = pose.matrix()
        views.append(View(image.name, np.asarray(cam.calibration_matrix(), dtype=float),
                          M[:, :3].copy(), M[:, 3].copy(), int(cam.width), int(cam.height)))
        point_ids.append([p.point3D_id for p in image.points2D if p.has_point3D()])
    xyz_by_id = {pid: np.asarray(p.xyz, dtype=float) for pid, p in rec.points3D.items()}
    return views, point_ids, xyz_by_id


def _choose(views, point_ids, xyz_by_id) -> list[list[int]]:
    from designer.sfm.stereo_pairs import choose_pairs

    n = len(views)
    shared = np.zeros((n, n), dtype=np.int64)
    owners: dict[int, list[int]] = {}
    for i, ids in enumerate(point_ids):
        for pid in set(ids):
            owners.setdefault(pid, []).append(i)
    for images in owners.values():
        idx = np.array(images)
        shared[np.ix_(idx, idx)] += 1
    depth = np.zeros(n)
    for i, ids in enumerate(point_ids):
        if ids:
            X = np.array([xyz_by_id[p] for p in ids])
            depth[i] = float(np.median((views[i].R @ X.T)[2] + views[i].t[2]))
    return choose_pairs(views, shared, depth, n_neighbours=N_NEIGHBOURS)


def _write_fusion_config(ws: Path, views) -> None:
    write_text_atomic(ws / "stereo" / "fusion.cfg", "".join(f"{v.name}\n" for v in views))


def _read_fused_ply(path: Path) -> tuple[np.ndarray, np.ndarray]:
    from plyfile import PlyData

    if not path.is_file():
        return np.zeros((0, 3)), np.zeros((0, 3), np.uint8)
    v = PlyData.read(str(path))["vertex"]
    xyz = np.column_stack([np.asarray(v[c], dtype=np.float64) for c in "xyz"])
    rgb = np.column_stack([np.asarray(v[c], dtype=np.uint8)
                           for c in ("red", "green", "blue")])
    return xyz, rgb


def write_dense_ply(path: str | os.PathLike, cloud: DenseCloud) -> Path:
    """The cloud as binary PLY: double x, y, z (world metres, full UTM precision) and
    uchar red, green, blue; written atomically."""
    from plyfile import PlyData, PlyElement

    data = np.empty(len(cloud), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8"),
                                       ("red", "u1"), ("green", "u1"), ("blue", "u1")])
    data["x"], data["y"], data["z"] = np.asarray(cloud.points_world, dtype=np.float64).T
    data["red"], data["green"], data["blue"] = np.asarray(cloud.colors_rgb, np.uint8).T
    path = Path(path)
    with atomic_path(path) as tmp:
        PlyData([PlyElement.describe(data, "vertex")],
                comments=[f"dense cloud: {cloud.matcher}"]).write(str(tmp))
    return path


def write_las(path: str | os.PathLike, cloud: DenseCloud, crs_epsg: int | None,
              offset_world) -> Path:
    """The cloud as LAS 1.4 (point format 7: XYZ and 16-bit RGB), LAZ-compressed when
    ``path`` ends in .laz (laspy with lazrs).

    Coordinates are stored as integers of 0.1 mm around ``offset_world`` (3,), rounded
    to whole metres: ±214 km around it fit. The CRS (EPSG code) goes into an OGC WKT
    coordinate-system VLR (WKT from GDAL via rasterio). Colours are scaled 8 → 16 bit
    (×257), so reading back and taking the high byte gives the original values."""
    import laspy
    from laspy.vlrs.known import WktCoordinateSystemVlr

    xyz = np.asarray(cloud.points_world, dtype=np.float64)
    offset = np.round(np.asarray(offset_world, dtype=np.float64).reshape(3))
    scale = 1e-4
    if len(xyz) and np.abs(xyz - offset).max() / scale >= 2**31 - 1:
        raise DesignerError(f"{path}: points lie more than 214 km from the LAS offset "
                            f"{offset.tolist()}; give an offset inside the survey")
    header = laspy.LasHeader(version="1.4", point_format=7)
    header.offsets = offset
    header.scales = np.full(3, scale)
    if crs_epsg is not None:
        import rasterio.crs
        from rasterio.errors import CRSError

        try:
            wkt = rasterio.crs.CRS.from_epsg(int(crs_epsg)).to_wkt()
        except (CRSError, ValueError):
            raise DesignerError(f"{path}: EPSG:{crs_epsg} is not a CRS GDAL knows; give "
                                "the project's EPSG code") from None
        header.vlrs.append(WktCoordinateSystemVlr(wkt))
        header.global_encoding.wkt = True
    las = laspy.LasData(header)
    las.x, las.y, las.z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    rgb = np.asarray(cloud.colors_rgb, dtype=np.uint16) * 257
    las.red, las.green, las.blue = rgb[:, 0], rgb[:, 1], rgb[:, 2]
    path = Path(path)
    with atomic_path(path) as tmp:
        las.write(str(tmp), do_compress=path.suffix.lower() == ".laz")
    return path
