"""Write the sample real site: a DEM and an orthophoto GeoTIFF pair, made in code.

    .venv/bin/python scripts/make-sample-site.py [--out resources/sites/sample] [--no-wgs84]

Writes ``dem.tif`` (120 x 90 m at 0.5 m, EPSG:32633), ``orthophoto.tif`` (99 x 78 m at
3 cm, another extent and pixel grid, six survey crosses at known coordinates) and
``dem-wgs84.tif`` (the same terrain on an EPSG:4326 grid) — see
designer/scene/sample_site.py. The same command always writes the same site; then

    designer new site.xml --site dem.tif --orthophoto orthophoto.tif
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from designer.scene.sample_site import write_sample_site  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "resources" / "sites" / "sample",
                        help="folder to write (default: resources/sites/sample)")
    parser.add_argument("--no-wgs84", action="store_true",
                        help="skip the geographic (EPSG:4326) copy of the DEM")
    args = parser.parse_args()
    for name, path in write_sample_site(args.out, geographic=not args.no_wgs84).items():
        print(f"wrote {path} ({path.stat().st_size / 1e6:.2f} MB, {name})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
