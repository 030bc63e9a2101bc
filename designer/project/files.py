"""Checks that files referenced by a project exist and are what their role needs.

Each check reads only a file's first bytes (its magic number or header), so checking a
project with a large DEM or texture stays fast. They return a sentence naming the
problem and the fix, or None when the file looks right.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

IMAGE_MAGIC = {
    b"\x89PNG\r\n\x1a\n": "PNG",
    b"\xff\xd8\xff": "JPEG",
    b"II*\x00": "TIFF",
    b"MM\x00*": "TIFF",
    b"v/1\x01": "EXR",
    b"BM": "BMP",
}
MESH_SUFFIXES = (".ply", ".obj", ".stl")
DEM_SUFFIXES = (".tif", ".tiff", ".asc")


def resolve(base_dir: Path, file: str) -> Path:
    """``file`` as written in the project, relative to the project's folder."""
    path = Path(os.path.expanduser(file.replace("\\", "/")))
    return path if path.is_absolute() else base_dir / path


def _head(path: Path, n: int = 4096) -> tuple[bytes | None, str | None]:
    """(first bytes, None) or (None, problem) for a missing or unreadable file."""
    if not path.exists():
        return None, f"file '{path}' does not exist"
    if not path.is_file():
        return None, f"'{path}' is not a file"
    try:
        with path.open("rb") as f:
            return f.read(n), None
    except OSError as error:
        return None, f"file '{path}' cannot be read ({error.strerror or error})"


def image_problem(path: Path) -> str | None:
    head, problem = _head(path, 16)
    if problem:
        return f"{problem}; give the path of an image, relative to the project file"
    for magic in IMAGE_MAGIC:
        if head.startswith(magic):
            return None
    return (f"file '{path}' is not a readable image (expected PNG, JPEG, TIFF, EXR or BMP "
            "data); convert it or give another file")


def orthophoto_problem(path: Path) -> str | None:
    head, problem = _head(path, 16)
    if problem:
        return f"{problem}; give the path of a GeoTIFF orthophoto, relative to the project file"
    if not head.startswith((b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+")):
        return (f"file '{path}' is not a TIFF/GeoTIFF file; an orthophoto must be a GeoTIFF "
                "(it carries its own georeferencing)")
    return None


def mesh_problem(path: Path) -> str | None:
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        return (f"file '{path}' has the extension '{suffix}', not a supported mesh format "
                "(.ply, .obj, .stl); convert it to one of them")
    head, problem = _head(path)
    if problem:
        return f"{problem}; give the path of a mesh, relative to the project file"
    if not head:
        return f"mesh file '{path}' is empty; export the mesh again"
    if suffix == ".ply" and not head.startswith(b"ply"):
        return f"file '{path}' is not a PLY mesh (it does not start with 'ply')"
    if suffix == ".obj" and not _looks_like_obj(head):
        return f"file '{path}' is not a Wavefront OBJ mesh (no 'v x y z' vertex lines)"
    if suffix == ".stl" and not _looks_like_stl(path, head):
        return f"file '{path}' is not an STL mesh (neither 'solid' text nor binary STL)"
    return None


def _looks_like_obj(head: bytes) -> bool:
    if b"\x00" in head:
        return False
    return any(line.strip().startswith((b"v ", b"v\t", b"o ", b"g ", b"#", b"mtllib"))
               for line in head.splitlines()[:50])


def _looks_like_stl(path: Path, head: bytes) -> bool:
    if head.lstrip().startswith(b"solid") and b"\x00" not in head[:512]:
        return True
    if len(head) < 84:
        return False
    triangles = int.from_bytes(head[80:84], "little")
    return path.stat().st_size == 84 + 50 * triangles


def dem_problem(path: Path) -> str | None:
    suffix = path.suffix.lower()
    if suffix not in DEM_SUFFIXES:
        return (f"file '{path}' has the extension '{suffix}', not a supported DEM format "
                "(GeoTIFF .tif/.tiff or ESRI ASCII grid .asc)")
    head, problem = _head(path)
    if problem:
        return f"{problem}; give the path of a DEM, relative to the project file"
    if suffix in (".tif", ".tiff"):
        if not head.startswith((b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+")):
            return f"file '{path}' is not a TIFF/GeoTIFF file; export the DEM as GeoTIFF"
        return None
    header = ascii_grid_header(head)
    if isinstance(header, str):
        return f"file '{path}' is not an ESRI ASCII grid: {header}"
    return None


def ascii_grid_header(head: bytes) -> dict[str, float] | str:
    """The header of an ESRI ASCII grid as numbers, or a sentence saying what is wrong."""
    values: dict[str, float] = {}
    for raw in head.splitlines()[:7]:
        parts = raw.decode("ascii", errors="replace").split()
        if len(parts) != 2 or not parts[0][:1].isalpha():
            break
        try:
            values[parts[0].lower()] = float(parts[1])
        except ValueError:
            return f"header value '{parts[1]}' of {parts[0]} is not a number"
    required = ("ncols", "nrows", "cellsize")
    missing = [k for k in required if k not in values]
    if missing:
        return "missing header line(s) " + ", ".join(missing)
    if not ({"xllcorner", "xllcenter"} & values.keys()
            and {"yllcorner", "yllcenter"} & values.keys()):
        return "missing xllcorner/yllcorner (or xllcenter/yllcenter) header lines"
    if not all(math.isfinite(v) for v in values.values()) or values["cellsize"] <= 0:
        return "header numbers must be finite and cellsize > 0"
    return values


def ascii_grid_extent(header: dict[str, float]) -> tuple[float, float, float, float]:
    """(min X, min Y, max X, max Y) covered by an ESRI ASCII grid's cells."""
    size = header["cellsize"]
    x0 = header.get("xllcorner", header.get("xllcenter", 0.0) - size / 2)
    y0 = header.get("yllcorner", header.get("yllcenter", 0.0) - size / 2)
    return x0, y0, x0 + header["ncols"] * size, y0 + header["nrows"] * size
