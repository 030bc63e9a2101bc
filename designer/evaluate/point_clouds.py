"""Read point clouds into world coordinates (float64): PLY, LAS/LAZ, XYZ/CSV/TXT, COLMAP.

World frame: X east, Y north, Z up, metres. Every reader returns a :class:`PointCloud`
with float64 coordinates; an ``offset`` (E0, N0, H0) given by the caller is added, for
clouds stored in local coordinates. A PLY header comment ``designer_origin_m E N H``
(written by designer's mesh writer) is added back as well.

* PLY (ASCII or binary, via plyfile): ``x, y, z`` of the ``vertex`` element (any numeric
  type), colours from ``red/green/blue`` (or ``r/g/b``, ``diffuse_*``), normals from
  ``nx/ny/nz``. Binary files are memory-mapped.
* LAS/LAZ (laspy; LAZ needs its ``lazrs`` or ``laszip`` backend): the scaled, offset
  coordinates; 16-bit colours are reduced to 8 bits.
* XYZ/CSV/TXT: delimiter sniffed (comma, semicolon, tab or spaces), '#' and '//'
  comment lines skipped except a '//X,Y,Z' header (CloudCompare's); columns found by
  name (x/y/z, e/n/h, easting/northing/height...) from a header row, else the first
  three; ``columns`` names them or gives 0-based numbers; colours from r/g/b columns.
* COLMAP: a model folder or its ``points3D.txt``/``.bin``.

Stored precision: a PLY with float32 coordinates at UTM size (COLMAP's own PLY export of
a model in world coordinates) is quantised in steps far above the errors being measured
(float32 spacing is 31 mm at 500 000 m, 0.5 m at 5 400 000 m); a LAS file quantises to
its scale. When that spacing exceeds :data:`MAX_COORDINATE_SPACING_M`,
:func:`read_point_cloud` refuses the cloud with the fix (a local frame plus ``offset``),
unless ``allow_coarse`` is given; the spacing is kept in
:attr:`PointCloud.coordinate_spacing_m` either way.

Problems raise :class:`DesignerError` with a one-line message naming the file.
"""

from __future__ import annotations

import io
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError

#: coarsest stored coordinate spacing read without ``allow_coarse`` (m)
MAX_COORDINATE_SPACING_M = 1e-3
PLY_SUFFIXES = (".ply",)
LAS_SUFFIXES = (".las", ".laz")
TEXT_SUFFIXES = (".xyz", ".csv", ".txt", ".asc", ".pts")
_NAMES = {
    "x": ("x", "e", "east", "easting", "//x", "x_m", "e_m"),
    "y": ("y", "n", "north", "northing", "y_m", "n_m"),
    "z": ("z", "h", "height", "elevation", "elev", "alt", "altitude", "z_m", "h_m"),
}


@dataclass(frozen=True, eq=False)
class PointCloud:
    """Points in world coordinates: ``xyz`` (N, 3) float64 metres; optional ``rgb``
    (N, 3) uint8 and ``normals`` (N, 3) float32; ``source`` names where they came from;
    ``coordinate_spacing_m``: the step of the coordinates as the file stores them (float32
    PLY: the float32 spacing at the largest |coordinate|; LAS: its scale), None when they
    are stored as doubles or text."""

    xyz: np.ndarray
    rgb: np.ndarray | None = None
    normals: np.ndarray | None = None
    source: str = ""
    coordinate_spacing_m: float | None = None

    def __len__(self) -> int:
        return len(self.xyz)


def _offset(offset) -> np.ndarray | None:
    if offset is None:
        return None
    off = np.asarray(offset, dtype=np.float64)
    if off.shape != (3,) or not np.isfinite(off).all():
        raise DesignerError(f"offset must be three finite numbers E N H, got {offset!r}")
    return off


def read_point_cloud(
    path: str | os.PathLike,
    *,
    offset=None,
    columns: tuple[str | int, str | int, str | int] | None = None,
    allow_coarse: bool = False,
    offset_hint=None,
) -> PointCloud:
    """Read the cloud at ``path`` (format from the suffix; a folder is a COLMAP model).

    A cloud whose stored coordinates are spaced more than :data:`MAX_COORDINATE_SPACING_M`
    apart (float32 at UTM size, a coarse LAS scale) is refused unless ``allow_coarse``;
    the error suggests ``offset_hint`` (E, N, H, or a function returning them or None,
    called only then; default: the cloud's centre rounded to 100 m) as the local frame
    to write it in.
    """
    path = Path(path)
    off = _offset(offset)
    if not path.exists():
        raise DesignerError(f"point cloud {path} does not exist")
    if path.is_dir() or path.name.lower().startswith("points3d"):
        from designer.export.colmap_read import model_files, read_points3d

        if path.is_dir() and model_files(path) is None and not any(
                (path / f"points3D{e}").is_file() for e in (".txt", ".bin")):
            raise DesignerError(f"{path} is a folder but not a COLMAP model (no points3D)")
        pts = read_points3d(path)
        cloud = PointCloud(pts.xyz, pts.rgb, None, str(path))
    else:
        suffix = path.suffix.lower()
        if path.stat().st_size == 0:
            raise DesignerError(f"point cloud {path} is empty")
        if suffix in PLY_SUFFIXES:
            cloud = _read_ply(path)
        elif suffix in LAS_SUFFIXES:
            cloud = _read_las(path)
        elif suffix in TEXT_SUFFIXES:
            cloud = _read_text(path, columns)
        else:
            raise DesignerError(f"point cloud {path}: unknown format '{path.suffix}'; use PLY, "
                                "LAS/LAZ, XYZ/CSV/TXT or a COLMAP model")
    if len(cloud.xyz) == 0:
        raise DesignerError(f"point cloud {path} has no points")
    xyz = cloud.xyz
    if not np.isfinite(xyz).all():
        bad = int(np.flatnonzero(~np.isfinite(xyz).all(axis=1))[0])
        raise DesignerError(f"point cloud {path}: point {bad} has a NaN or infinite coordinate")
    spacing = cloud.coordinate_spacing_m
    if spacing is not None and spacing > MAX_COORDINATE_SPACING_M and not allow_coarse:
        raise DesignerError(coarse_message(path, xyz, spacing, offset_hint))
    if off is not None:
        xyz = xyz + off
    return PointCloud(xyz, cloud.rgb, cloud.normals, str(path), spacing)


def float32_spacing_m(stored_xyz: np.ndarray) -> float:
    """The float32 spacing (m) at the largest |coordinate| of ``stored_xyz``."""
    max_abs = float(np.max(np.abs(stored_xyz))) if stored_xyz.size else 0.0
    return float(np.spacing(np.float32(max_abs)))


def coarse_message(path: Path, xyz: np.ndarray, spacing_m: float, offset_hint=None) -> str:
    """One line: why the coordinates of ``path`` are too coarse, and the fix."""
    max_abs = float(np.max(np.abs(xyz)))
    if callable(offset_hint):
        offset_hint = offset_hint()
    hint = (np.asarray(offset_hint, float) if offset_hint is not None
            else np.round((xyz.min(axis=0) + xyz.max(axis=0)) / 2, -2))
    hint_text = " ".join(f"{v:.10g}" for v in hint)
    if path.suffix.lower() in LAS_SUFFIXES:
        stored = f"coordinates stored with a scale of {spacing_m * 1000:.3g} mm"
        rewrite = "write it with a scale of 0.001 m or finer"
    else:
        stored = (f"coordinates stored as float32 up to |{max_abs:.0f}| m, where float32 "
                  f"spacing is {spacing_m * 1000:.4g} mm")
        rewrite = (f"write it in a local frame (coordinates minus an offset such as "
                   f"{hint_text}) and pass --offset {hint_text}, which is added in float64 "
                   "after reading, or give the tool's model instead (a COLMAP model folder "
                   "holds doubles)")
    return (f"point cloud {path}: {stored}, coarser than the "
            f"{MAX_COORDINATE_SPACING_M * 1000:g} mm the comparison resolves; {rewrite}; or "
            "pass --allow-float32 to compare it anyway (the spacing is recorded in "
            "summary.json)")


# --------------------------------------------------------------------------- PLY
def _read_ply(path: Path) -> PointCloud:
    from plyfile import PlyData, PlyElementParseError, PlyHeaderParseError

    from designer.scene.mesh import origin_from_ply_comments

    try:
        try:
            ply = PlyData.read(str(path))  # memory-maps binary vertex data
        except PlyElementParseError:
            ply = PlyData.read(str(path), mmap=False)
    except (PlyHeaderParseError, PlyElementParseError, ValueError, OSError) as exc:
        detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DesignerError(f"point cloud {path} is not a valid PLY ({detail})") from None
    if "vertex" not in [e.name for e in ply.elements]:
        raise DesignerError(f"point cloud {path} has no 'vertex' element")
    vert = ply["vertex"].data
    names = set(vert.dtype.names or ())
    if not {"x", "y", "z"} <= names:
        raise DesignerError(f"point cloud {path}: vertices have no x, y, z properties "
                            f"(found {sorted(names)})")
    xyz = np.empty((len(vert), 3))
    for i, c in enumerate("xyz"):
        xyz[:, i] = vert[c]
    spacing = None
    if any(vert.dtype[c].kind == "f" and vert.dtype[c].itemsize <= 4 for c in "xyz"):
        spacing = float32_spacing_m(xyz)  # stored values, before any origin is added
    origin = origin_from_ply_comments(path, ply.comments)
    if origin is not None:
        xyz += origin
    rgb = None
    for r, g, b in (("red", "green", "blue"), ("r", "g", "b"),
                    ("diffuse_red", "diffuse_green", "diffuse_blue")):
        if {r, g, b} <= names:
            rgb = _to_uint8(np.column_stack([vert[r], vert[g], vert[b]]))
            break
    normals = None
    if {"nx", "ny", "nz"} <= names:
        normals = np.column_stack([vert["nx"], vert["ny"], vert["nz"]]).astype(np.float32)
    return PointCloud(xyz, rgb, normals, str(path), spacing)


def _to_uint8(values: np.ndarray) -> np.ndarray:
    if np.issubdtype(values.dtype, np.floating) and values.size and values.max() <= 1.0:
        return np.clip(np.round(values * 255), 0, 255).astype(np.uint8)
    if values.size and values.max() > 255:  # 16-bit colours (LAS)
        return (values // 257).astype(np.uint8)
    return np.clip(values, 0, 255).astype(np.uint8)


# --------------------------------------------------------------------------- LAS/LAZ
def _read_las(path: Path) -> PointCloud:
    try:
        import laspy
    except ImportError:
        raise DesignerError(f"point cloud {path}: reading LAS/LAZ needs laspy "
                            "(pip install 'laspy[lazrs]')") from None
    try:
        las = laspy.read(str(path))
    except laspy.errors.LaspyException as exc:
        detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        hint = "; LAZ needs lazrs: pip install 'laspy[lazrs]'" if "backend" in detail.lower() \
            or "laz" in detail.lower() else ""
        raise DesignerError(f"point cloud {path} cannot be read as LAS/LAZ ({detail}){hint}") \
            from None
    except (ValueError, OSError) as exc:
        raise DesignerError(f"point cloud {path} cannot be read as LAS/LAZ ({exc})") from None
    xyz = np.column_stack([np.asarray(las.x, np.float64), np.asarray(las.y, np.float64),
                           np.asarray(las.z, np.float64)])
    rgb = None
    dims = set(las.point_format.dimension_names)
    if {"red", "green", "blue"} <= dims:
        rgb = _to_uint8(np.column_stack([las.red, las.green, las.blue]))
    spacing = float(np.max(np.abs(np.asarray(las.header.scales, np.float64))))
    return PointCloud(xyz, rgb, None, str(path), spacing)


# --------------------------------------------------------------------------- text
def _read_text(path: Path, columns) -> PointCloud:
    try:
        text = path.read_text(encoding="utf-8", errors="strict")
    except UnicodeDecodeError:
        text = "\0"
    if "\0" in text:
        raise DesignerError(f"point cloud {path} is not a text file; is it binary?")
    header, body = _split_header(text)
    if not body:
        raise DesignerError(f"point cloud {path} has no data rows")
    delimiter = _sniff_delimiter(body[0])
    names = [h.strip().lower() for h in _split(header, delimiter)] if header else None
    first = _split(body[0], delimiter)
    cols = _pick_columns(path, names, len(first), columns)
    rgb_cols = None
    if names is not None:
        for triple in (("r", "g", "b"), ("red", "green", "blue")):
            if set(triple) <= set(names):
                rgb_cols = [names.index(n) for n in triple]
                break
    wanted = cols + (rgb_cols or [])
    try:
        table = np.loadtxt(io.StringIO("\n".join(body)), delimiter=delimiter, ndmin=2,
                           usecols=wanted, dtype=np.float64)
    except (ValueError, IndexError) as exc:
        raise DesignerError(f"point cloud {path}: cannot read columns {wanted} of every row "
                            f"as numbers ({str(exc).splitlines()[0]})") from None
    rgb = _to_uint8(table[:, 3:6]) if rgb_cols else None
    return PointCloud(np.ascontiguousarray(table[:, :3]), rgb, None, str(path))


def _split_header(text: str) -> tuple[str | None, list[str]]:
    header, body = None, []
    for line in text.splitlines():
        s = line.strip()
        if not s:
            continue
        if s.startswith("//") and not body and re.match(r"//\s*x\b", s, re.IGNORECASE):
            header = s[2:]
            continue
        if s.startswith(("#", "//")):
            continue
        if not body and header is None and re.search(r"[A-Za-z_]", s) and not _numeric(s):
            header = s
            continue
        body.append(s)
    return header, body


def _numeric(line: str) -> bool:
    try:
        [float(v) for v in _split(line, _sniff_delimiter(line))]
    except ValueError:
        return False
    return True


def _sniff_delimiter(line: str) -> str | None:
    for d in (",", ";", "\t"):
        if d in line:
            return d
    return None


def _split(line: str, delimiter: str | None) -> list[str]:
    return [v.strip() for v in (line.split(delimiter) if delimiter else line.split())]


def _pick_columns(path: Path, names, n_columns: int, columns) -> list[int]:
    if columns is not None:
        if len(columns) != 3:
            raise DesignerError(f"columns must name three columns (x, y, z), got {columns!r}")
        out = []
        for c in columns:
            if isinstance(c, int) or (isinstance(c, str) and c.isdigit()):
                out.append(int(c))
            elif names is not None and c.strip().lower() in names:
                out.append(names.index(c.strip().lower()))
            else:
                raise DesignerError(f"point cloud {path}: no column {c!r}"
                                    + (f" (columns: {', '.join(names)})" if names else
                                       " (the file has no header row)"))
        if max(out) >= n_columns:
            raise DesignerError(f"point cloud {path}: rows have {n_columns} columns, column "
                                f"{max(out)} was asked for")
        return out
    if n_columns < 3:
        raise DesignerError(f"point cloud {path}: rows have {n_columns} columns; x, y, z need 3")
    if names is None:
        return [0, 1, 2]
    found = []
    for axis in "xyz":
        hit = next((names.index(n) for n in _NAMES[axis] if n in names), None)
        if hit is None:
            raise DesignerError(f"point cloud {path}: no {axis} column in the header "
                                f"({', '.join(names)}); name them with --columns")
        found.append(hit)
    return found
