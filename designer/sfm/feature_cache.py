"""A cache of COLMAP feature databases shared by reconstructions of the same images.

Reconstructions that differ only in what happens after matching (GCP roles, marking
error, calibration mode, priors, filters) extract the same SIFT features and match the
same pairs; those that differ only after structure from motion (GCP mode, marking error,
control selection, filters) also find the same cameras and tie points. The cache keeps,
per content key, the COLMAP database after feature extraction and after matching, and
the model the SfM mapper found::

    ROOT/features-KEY/database.db    features of the images
    ROOT/matches-KEY/database.db     … and the matches of the pairs
    ROOT/sfm-KEY/model/              the mapper's model (COLMAP's binary files), before
                                     any georeferencing
    ROOT/*.lock                      one lock per key (held while it is computed)

Keys hash everything the step's result depends on: the images' bytes and names, the
camera model and its starting parameters (stored in the database), the SIFT and
matching options and the pycolmap version; the match key adds the pair list; the SfM
key adds the mapper, the interior parameters it refines and the rig layout. A second
process asking for a key that is being computed waits for it (``fcntl`` file lock) and
then copies it, so concurrent runs of a study never extract the same images twice.
Entries are complete or absent: a database enters the cache by an atomic rename.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import os
import shutil
from collections.abc import Iterator
from pathlib import Path

DB_NAME = "database.db"


def images_digest(image_dir: Path, names: list[str]) -> str:
    """SHA-256 over the images' names and bytes (in the given order)."""
    h = hashlib.sha256()
    for name in names:
        h.update(name.encode() + b"\x00")
        with open(Path(image_dir) / name, "rb") as f:
            for chunk in iter(lambda: f.read(1 << 20), b""):
                h.update(chunk)
    return h.hexdigest()


def key(*parts: object) -> str:
    """A short content key of the parts' text."""
    import pycolmap

    h = hashlib.sha256(pycolmap.__version__.encode())
    for part in parts:
        h.update(b"\x00" + str(part).encode())
    return h.hexdigest()[:24]


class FeatureCache:
    """Databases by kind (``features``/``matches``) and key under ``root``."""

    def __init__(self, root: Path) -> None:
        self.root = Path(root)

    def _entry(self, kind: str, k: str) -> Path:
        return self.root / f"{kind}-{k}" / DB_NAME

    @contextlib.contextmanager
    def hold(self, kind: str, k: str) -> Iterator[None]:
        """Exclusive use of one key: compute-or-fetch happens once across processes."""
        self.root.mkdir(parents=True, exist_ok=True)
        with open(self.root / f"{kind}-{k}.lock", "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)

    def fetch(self, kind: str, k: str, db_path: Path) -> bool:
        """Copy the cached database to ``db_path``; False if there is none."""
        entry = self._entry(kind, k)
        if not entry.is_file():
            return False
        tmp = Path(f"{db_path}.part")
        shutil.copyfile(entry, tmp)
        os.replace(tmp, db_path)
        return True

    def store(self, kind: str, k: str, db_path: Path) -> None:
        """Put a copy of ``db_path`` into the cache (atomically)."""
        entry = self._entry(kind, k)
        entry.parent.mkdir(parents=True, exist_ok=True)
        tmp = entry.with_name(f".{DB_NAME}.part")
        shutil.copyfile(db_path, tmp)
        os.replace(tmp, entry)

    def fetch_model(self, k: str, model_dir: Path) -> bool:
        """Copy the cached SfM model into ``model_dir`` (created); False if there is none."""
        entry = self.root / f"sfm-{k}" / "model"
        if not entry.is_dir():
            return False
        if model_dir.exists():
            shutil.rmtree(model_dir)
        shutil.copytree(entry, model_dir)
        return True

    def store_model(self, k: str, rec) -> None:
        """Put the pycolmap Reconstruction ``rec`` into the cache (atomically: written
        beside, then renamed into place)."""
        entry = self.root / f"sfm-{k}" / "model"
        entry.parent.mkdir(parents=True, exist_ok=True)
        tmp = entry.with_name(".model.part")
        if tmp.exists():
            shutil.rmtree(tmp)
        tmp.mkdir()
        rec.write(str(tmp))
        os.replace(tmp, entry)
