"""Do images of a rendered survey match where their footprints do not overlap?

    python scripts/texture-repeat-matching.py OUT IMG_A IMG_B [IMG_C ...]

OUT is a folder ``designer render`` wrote (images in OUT/images/ or OUT/, and
ground-truth/). For every pair of
the named images this prints:

* OpenCV: SIFT (8000 features; keypoints within 40 px of a GCP target left out, the
  targets are identical checkerboards), Lowe's ratio test (0.8) both ways, mutual
  matches, RANSAC fundamental-matrix inliers at 4 px and 1 px, and the same RANSAC on
  the matches shuffled (what random matches give);
* pycolmap: SIFT extraction, exhaustive matching and two-view geometry with COLMAP's
  defaults: raw matches and verified inliers.

Used for the figures of docs/world.md, "Ground texture that does not repeat".
"""

from __future__ import annotations

import csv
import itertools
import shutil
import sqlite3
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

TARGET_RADIUS_PX = 40


def image_folder(out: Path) -> Path:
    return out / "images" if (out / "images").is_dir() else out


def opencv_pairs(folder: Path, names: list[str]) -> None:
    lines = [ln for ln in open(folder / "ground-truth" / "gcp_observations.csv")
             if not ln.startswith("#")]
    targets: dict[str, list] = {}
    for row in csv.DictReader(lines):
        targets.setdefault(row["image"], []).append((float(row["u_px"]), float(row["v_px"])))
    sift = cv2.SIFT_create(nfeatures=8000)

    def features(name):
        kp, desc = sift.detectAndCompute(cv2.imread(str(image_folder(folder) / name), 0), None)
        pts = np.float32([p.pt for p in kp])
        keep = np.ones(len(kp), bool)
        for t in targets.get(name, []):
            keep &= np.hypot(*(pts - np.float32(t)).T) > TARGET_RADIUS_PX
        return pts[keep], desc[keep]

    feats = {n: features(n) for n in names}
    matcher = cv2.BFMatcher(cv2.NORM_L2)

    def ratio(d1, d2):
        return {a.queryIdx: a.trainIdx for a, b in matcher.knnMatch(d1, d2, k=2)
                if a.distance < 0.8 * b.distance}

    rng = np.random.default_rng(0)
    for a, b in itertools.combinations(names, 2):
        (ka, da), (kb, db) = feats[a], feats[b]
        ab, ba = ratio(da, db), ratio(db, da)
        pairs = [(i, j) for i, j in ab.items() if ba.get(j) == i]
        pa, pb = ka[[i for i, _ in pairs]], kb[[j for _, j in pairs]]
        out = [f"opencv  {a} - {b}: mutual {len(pairs):5d}"]
        for thr in (4.0, 1.0):
            _, mask = cv2.findFundamentalMat(pa, pb, cv2.FM_RANSAC, thr, 0.999, 10000)
            _, rand = cv2.findFundamentalMat(pa, pb[rng.permutation(len(pb))], cv2.FM_RANSAC,
                                             thr, 0.999, 10000)
            out.append(f"F inliers @{thr:g} px {int(mask.sum()):5d} "
                       f"(shuffled {int(rand.sum()):3d})")
        print("  ".join(out))


def colmap_pairs(folder: Path, names: list[str]) -> None:
    import pycolmap

    with tempfile.TemporaryDirectory() as tmp:
        images = Path(tmp) / "images"
        images.mkdir()
        for n in names:
            shutil.copy(image_folder(folder) / n, images / n)
        db = Path(tmp) / "database.db"
        pycolmap.extract_features(db, images)
        pycolmap.match_exhaustive(db)
        con = sqlite3.connect(db)
        ids = dict(con.execute("select image_id, name from images"))

        def pair(pair_id):
            b = pair_id % 2147483647
            return ids[(pair_id - b) // 2147483647], ids[b]

        raw = {pair(p): r for p, r in con.execute("select pair_id, rows from matches")}
        for p, rows in con.execute("select pair_id, rows from two_view_geometries"):
            a, b = pair(p)
            print(f"pycolmap {a} - {b}: raw matches {raw.get((a, b), 0):5d}  "
                  f"verified inliers {rows:5d}")
        con.close()


if __name__ == "__main__":
    out, *images = sys.argv[1:]
    opencv_pairs(Path(out), images)
    colmap_pairs(Path(out), images)
