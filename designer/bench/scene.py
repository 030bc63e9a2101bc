"""Scene generation throughput (``designer bench scene``): terrain, mesh, PLY, texture."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

from designer.bench.table import Column, text_table
from designer.bench.timing import best_of
from designer.scene.mesh import heightfield_to_mesh, write_mesh_ply
from designer.scene.terrain import procedural_terrain
from designer.scene.texture import procedural_texture


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    """Time the standard cases; ``scale`` shrinks the vertex and texel counts for tests.

    1 km² of procedural terrain at 1 m spacing (1001² ≈ 1 M vertices), its mesh
    (2 M triangles), the binary PLY of that mesh, and a 4096² grass texture.
    """
    side_m = 1000.0
    cells = max(2, round(1000 * math.sqrt(scale)))
    spacing_m = side_m / cells
    tex_px = max(64, round(4096 * math.sqrt(scale)))
    rows = []

    seconds, hf = best_of(repeats, lambda: procedural_terrain(
        side_m, side_m, spacing_m, 25.0, seed=1, x0_m=500000.0, y0_m=5000000.0,
        base_height_m=300.0))
    n_vertices = hf.heights_m.size
    rows.append({"step": "procedural terrain", "size": f"{n_vertices / 1e6:.2f} M vertices",
                 "seconds": seconds, "rate": f"{n_vertices / seconds / 1e6:.1f} M vertices/s"})

    seconds, mesh = best_of(repeats, lambda: heightfield_to_mesh(hf))
    n_faces = len(mesh.faces)
    rows.append({"step": "mesh height field", "size": f"{n_faces / 1e6:.2f} M triangles",
                 "seconds": seconds, "rate": f"{n_faces / seconds / 1e6:.1f} M triangles/s"})

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "terrain.ply"
        seconds, _ = best_of(repeats, lambda: write_mesh_ply(mesh, path))
        megabytes = path.stat().st_size / 1e6
    rows.append({"step": "write binary PLY", "size": f"{megabytes:.0f} MB",
                 "seconds": seconds, "rate": f"{megabytes / seconds:.0f} MB/s"})

    seconds, _ = best_of(repeats, lambda: procedural_texture(tex_px, seed=1, kind="grass"))
    megatexels = tex_px * tex_px / 1e6
    rows.append({"step": "procedural texture", "size": f"{tex_px}² texels",
                 "seconds": seconds, "rate": f"{megatexels / seconds:.1f} M texels/s"})
    return rows


def format_table(rows: list[dict]) -> str:
    return text_table(
        [Column("step", "<20", "step"), Column("size", "<18", "size"),
         Column("seconds", ">9.3f", "seconds"), Column("rate", ">22", "rate")], rows,
        "(one process; the FFTs use all cores, the rest one thread; best of the repeats; "
        "the PLY goes to the temporary folder)")
