"""A small, real-looking sample site: a DEM and an orthophoto as GeoTIFFs, made in code.

The site lies in UTM zone 33N (EPSG:32633), near 15.43° E, 47.07° N:

* ``dem.tif`` — 120 m × 90 m at 0.5 m (240 × 180 float32 cells, heights 300–320 m):
  rolling hills, a road cut 1.5 m deep along a gentle curve, three building blocks
  5–7 m high. Each cell holds the height at its centre.
* ``orthophoto.tif`` — 99 m × 78 m at 3 cm (3300 × 2600 px, RGB, JPEG-compressed), on
  another extent and pixel grid than the DEM (it reaches 9 m past the DEM's east edge
  and 6 m past its south edge; its corner is not on the DEM's 0.5 m grid): fields of
  grass and soil, the asphalt road with painted edge and dashed centre lines, roofs,
  and six survey crosses at :data:`CROSSES_EN` — white crosses on black squares drawn
  with exact pixel-area coverage, so each cross's centroid is its coordinate.
* ``dem-wgs84.tif`` (optional) — the same terrain sampled on a geographic grid
  (EPSG:4326, about 0.5 m cells), to exercise reprojection.

The terrain is an analytic function of (E, N) (:func:`height_m`), so any sampling of it —
the UTM grid, the geographic grid — is exact and comparable. Everything is seeded: the
same call writes the same rasters (JPEG coding aside, which depends on the library).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path
from designer.scene.texture import procedural_texture

EPSG = 32633
#: DEM: outer top-left corner (E, N), cell size, columns, rows
DEM_WEST, DEM_NORTH, DEM_CELL_M, DEM_COLS, DEM_ROWS = 533000.0, 5213090.0, 0.5, 240, 180
#: orthophoto: outer top-left corner (E, N), pixel size, columns, rows
ORTHO_WEST, ORTHO_NORTH, ORTHO_PIXEL_M, ORTHO_COLS, ORTHO_ROWS = (
    533029.985, 5213072.01, 0.03, 3300, 2600)
#: survey crosses painted in the orthophoto: centres (E, N), world m
CROSSES_EN = (
    (533041.37, 5213012.61), (533068.52, 5213015.08), (533098.94, 5213010.47),
    (533044.16, 5213058.33), (533071.73, 5213061.29), (533101.08, 5213055.72),
)
#: cross geometry (m): black square side, white arm length (tip to tip) and width
CROSS_SQUARE_M, CROSS_ARM_M, CROSS_WIDTH_M = 1.6, 1.2, 0.2
#: building blocks: (E min, N min, E max, N max, height above the ground at the centre, m)
BLOCKS = ((533012.0, 5213066.0, 533026.0, 5213078.0, 6.0),
          (533052.0, 5213046.0, 533062.0, 5213054.0, 5.0),
          (533086.0, 5213072.0, 533104.0, 5213082.0, 7.0))
ROAD_HALF_WIDTH_M, ROAD_CUT_M = 3.0, 1.5

_HILLS_SEED = 20240618


def _hills() -> np.ndarray:
    """(k, 4) Gaussian hills: centre E, centre N, sigma m, amplitude m (seeded)."""
    rng = np.random.default_rng(_HILLS_SEED)
    k = 9
    return np.column_stack([
        DEM_WEST - 20 + rng.uniform(0, 160, k), DEM_NORTH - 110 + rng.uniform(0, 130, k),
        rng.uniform(18, 45, k), rng.uniform(-4, 8, k)])


def road_offset_m(E, N) -> np.ndarray:
    """Signed distance (m, approximately) across the road's centre line, which runs
    west–east at N ≈ 5213036 with a gentle 4 m swing."""
    E = np.asarray(E, dtype=np.float64)
    centre_N = 5213036.0 + 4.0 * np.sin((E - DEM_WEST) / 120.0 * np.pi)
    return np.asarray(N, dtype=np.float64) - centre_N


def height_m(E, N) -> np.ndarray:
    """Terrain height (world Z, m) at world (E, N) in EPSG:32633: hills, road cut, blocks."""
    E = np.asarray(E, dtype=np.float64)
    N = np.asarray(N, dtype=np.float64)
    z = ground_height_m(E, N)
    for e0, n0, e1, n1, h in BLOCKS:
        inside = (E >= e0) & (E <= e1) & (N >= n0) & (N <= n1)
        roof = float(ground_height_m((e0 + e1) / 2, (n0 + n1) / 2)) + h
        z = np.where(inside, roof, z)
    return z


def ground_height_m(E, N) -> np.ndarray:
    """The ground without the blocks: a tilted plane, Gaussian hills, the road cut (m)."""
    E = np.asarray(E, dtype=np.float64)
    N = np.asarray(N, dtype=np.float64)
    x, y = E - DEM_WEST, N - (DEM_NORTH - DEM_ROWS * DEM_CELL_M)
    z = 304.0 + 0.03 * x + 0.02 * y
    for e0, n0, sigma, amp in _hills():
        z = z + amp * np.exp(-((E - e0) ** 2 + (N - n0) ** 2) / (2 * sigma * sigma))
    d = np.abs(road_offset_m(E, N))
    return z - ROAD_CUT_M * (1.0 - _smoothstep(d, ROAD_HALF_WIDTH_M + 0.5,
                                               ROAD_HALF_WIDTH_M + 4.0))


def _smoothstep(x, lo, hi):
    t = np.clip((x - lo) / (hi - lo), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


# --------------------------------------------------------------------------- rasters
def dem_heights() -> np.ndarray:
    """(rows, cols) float64 heights of ``dem.tif``, row 0 the northernmost (file order)."""
    cols = DEM_WEST + (np.arange(DEM_COLS) + 0.5) * DEM_CELL_M
    rows = DEM_NORTH - (np.arange(DEM_ROWS) + 0.5) * DEM_CELL_M
    E, N = np.meshgrid(cols, rows)
    return height_m(E, N)


def orthophoto_rgb() -> np.ndarray:
    """(rows, cols, 3) uint8 RGB of ``orthophoto.tif``, row 0 at the top (north)."""
    p = ORTHO_PIXEL_M
    E_edges = ORTHO_WEST + np.arange(ORTHO_COLS + 1) * p  # pixel edges, west → east
    N_edges = ORTHO_NORTH - np.arange(ORTHO_ROWS + 1) * p  # north → south
    E = (E_edges[:-1] + E_edges[1:])[None, :] / 2
    N = (N_edges[:-1] + N_edges[1:])[:, None] / 2
    grass = procedural_texture((ORTHO_COLS, ORTHO_ROWS), seed=31, kind="grass")
    soil = procedural_texture((ORTHO_COLS, ORTHO_ROWS), seed=32, kind="soil")
    img = grass.astype(np.float32) / 255.0
    # Fields: parcels bounded by slanted lines; every other parcel is ploughed soil.
    parcel = np.floor((E - 533000.0 + 0.35 * (N - 5213000.0)) / 27.0).astype(int)
    ploughed = (parcel % 2 == 1) & (road_offset_m(E, N) > 0)
    furrows = 0.85 + 0.15 * np.sin((E + 0.35 * N) * 2 * np.pi / 0.9)
    img = np.where(ploughed[..., None], soil.astype(np.float32) / 255.0 * furrows[..., None],
                   img)
    # The road: asphalt with painted edge lines and a dashed centre line.
    d = road_offset_m(E, N)
    asphalt = 0.30 + 0.03 * (grass[..., 1].astype(np.float32) / 255.0 - 0.3)
    on_road = np.abs(d) <= ROAD_HALF_WIDTH_M
    img = np.where(on_road[..., None], asphalt[..., None] * np.array([1.0, 1.0, 1.04]), img)
    edge_line = on_road & (np.abs(np.abs(d) - (ROAD_HALF_WIDTH_M - 0.25)) < 0.06)
    dash = (np.abs(d) < 0.06) & (np.mod(E - 533000.0, 6.0) < 3.0)
    img = np.where((edge_line | dash)[..., None], np.float32(0.92), img)
    # Roofs: red-brown tiles with ridges.
    for e0, n0, e1, n1, _ in BLOCKS:
        inside = (E >= e0) & (E <= e1) & (N >= n0) & (N <= n1)
        ridge = 0.85 + 0.15 * (N > (n0 + n1) / 2)
        roof = np.stack([0.55 * ridge, 0.24 * ridge, 0.18 * ridge], axis=-1)
        img = np.where(inside[..., None], roof, img)
    for e, n in CROSSES_EN:
        _draw_cross(img, E_edges, N_edges, e, n)
    return np.clip(img * 255.0 + 0.5, 0, 255).astype(np.uint8)


def _overlap_1d(lo_edges: np.ndarray, hi_edges: np.ndarray, a: float, b: float) -> np.ndarray:
    return np.clip(np.minimum(hi_edges, b) - np.maximum(lo_edges, a), 0.0, None)


def _rect_coverage(E_edges, N_edges, e0, n0, e1, n1) -> np.ndarray:
    """Fraction (rows, cols) of each pixel's area inside the rectangle (exact)."""
    p = E_edges[1] - E_edges[0]
    fx = _overlap_1d(E_edges[:-1], E_edges[1:], e0, e1) / p
    fy = _overlap_1d(N_edges[1:], N_edges[:-1], n0, n1) / p
    return fy[:, None] * fx[None, :]


def _draw_cross(img, E_edges, N_edges, e, n) -> None:
    """A black square with a white cross centred on (e, n), blended by pixel coverage."""
    h, a, w = CROSS_SQUARE_M / 2, CROSS_ARM_M / 2, CROSS_WIDTH_M / 2
    square = _rect_coverage(E_edges, N_edges, e - h, n - h, e + h, n + h)
    white = (_rect_coverage(E_edges, N_edges, e - a, n - w, e + a, n + w)
             + _rect_coverage(E_edges, N_edges, e - w, n - a, e + w, n + a)
             - _rect_coverage(E_edges, N_edges, e - w, n - w, e + w, n + w))
    black, bright = np.float32(0.04), np.float32(0.95)
    img *= (1.0 - square)[..., None]
    img += (square * black + white * (bright - black))[..., None]


def write_sample_site(folder: str | os.PathLike, geographic: bool = True) -> dict[str, Path]:
    """Write ``dem.tif``, ``orthophoto.tif`` (and ``dem-wgs84.tif``) into ``folder``.

    Returns the paths by name ('dem', 'orthophoto', 'dem_wgs84'). Each file is written
    atomically.
    """
    import rasterio
    from affine import Affine

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = {"dem": folder / "dem.tif", "orthophoto": folder / "orthophoto.tif"}
    crs = f"EPSG:{EPSG}"
    with atomic_path(out["dem"]) as tmp:
        with rasterio.open(tmp, "w", driver="GTiff", width=DEM_COLS, height=DEM_ROWS, count=1,
                           dtype="float32", crs=crs, compress="deflate", predictor=3,
                           transform=Affine(DEM_CELL_M, 0, DEM_WEST, 0, -DEM_CELL_M,
                                            DEM_NORTH)) as dst:
            dst.write(dem_heights().astype(np.float32), 1)
    rgb = orthophoto_rgb()
    with atomic_path(out["orthophoto"]) as tmp:
        with rasterio.open(tmp, "w", driver="GTiff", width=ORTHO_COLS, height=ORTHO_ROWS,
                           count=3, dtype="uint8", crs=crs, compress="jpeg", jpeg_quality=90,
                           photometric="ycbcr", tiled=True, blockxsize=256, blockysize=256,
                           transform=Affine(ORTHO_PIXEL_M, 0, ORTHO_WEST, 0, -ORTHO_PIXEL_M,
                                            ORTHO_NORTH)) as dst:
            dst.write(np.moveaxis(rgb, -1, 0))
    if geographic:
        out["dem_wgs84"] = folder / "dem-wgs84.tif"
        _write_geographic_dem(out["dem_wgs84"])
    return out


def _write_geographic_dem(path: Path) -> None:
    """The terrain sampled on an EPSG:4326 grid of about 0.5 m cells over the DEM's area."""
    import rasterio
    from affine import Affine
    from pyproj import Transformer

    to_geo = Transformer.from_crs(EPSG, 4326, always_xy=True)
    to_utm = Transformer.from_crs(4326, EPSG, always_xy=True)
    e = [DEM_WEST, DEM_WEST + DEM_COLS * DEM_CELL_M]
    n = [DEM_NORTH - DEM_ROWS * DEM_CELL_M, DEM_NORTH]
    lon, lat = to_geo.transform([e[0], e[1], e[0], e[1]], [n[0], n[0], n[1], n[1]])
    lat_c = np.radians(np.mean(lat))
    dlat = DEM_CELL_M / 111_132.0
    dlon = DEM_CELL_M / (111_320.0 * np.cos(lat_c))
    west, north = min(lon), max(lat)
    cols = int(np.ceil((max(lon) - west) / dlon))
    rows = int(np.ceil((north - min(lat)) / dlat))
    lon_c = west + (np.arange(cols) + 0.5) * dlon
    lat_c = north - (np.arange(rows) + 0.5) * dlat
    LON, LAT = np.meshgrid(lon_c, lat_c)
    E, N = to_utm.transform(LON, LAT)
    with atomic_path(path) as tmp:
        with rasterio.open(tmp, "w", driver="GTiff", width=cols, height=rows, count=1,
                           dtype="float32", crs="EPSG:4326", compress="deflate", predictor=3,
                           transform=Affine(dlon, 0, west, 0, -dlat, north)) as dst:
            dst.write(height_m(E, N).astype(np.float32), 1)
