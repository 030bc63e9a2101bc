"""Content hashes of what each stage of a study depends on.

* image set: the per-image provenance digests of the prepared render job
  (:func:`designer.render.provenance.job_provenance`) and the image names — two runs
  with equal image-set hashes have identical images, so they are rendered once;
* raw set: the same without the camera effects
  (:func:`designer.render.provenance.raw_render_digests`) — image sets with equal raw
  sets differ only in their effects: Cycles renders one of them, the others are effect
  passes over its kept raw renders;
* processing: the image set, the ground-truth tables written for the run (GCP survey
  error, roles) and the ``<processing>`` settings — equal hashes reconstruct once.
"""

from __future__ import annotations

import hashlib
import json

from designer import __version__


def digest(*chunks: str) -> str:
    h = hashlib.sha256()
    for c in chunks:
        h.update(c.encode())
        h.update(b"\x00")
    return h.hexdigest()[:24]


def image_set_hash(provenance: dict, image_names: dict[int, str]) -> str:
    """Hash of a render job's images: each image's name and input digest."""
    return digest("images", *(f"{image_names[i]}={provenance[i].digest}"
                               for i in sorted(provenance)))


def raw_set_hash(raw_digests: dict[int, str], image_names: dict[int, str]) -> str:
    """Hash of a render job's raw renders (Blender's images before the camera effects):
    image sets with equal raw-set hashes render in Cycles once, the others of them are
    effect passes over the kept raw renders."""
    return digest("raw", *(f"{image_names[i]}={raw_digests[i]}" for i in sorted(raw_digests)))


def processing_hash(image_hash: str, ground_truth_digest: str, processing, mode: str) -> str:
    """Hash of a reconstruction's inputs: images, ground truth, settings, software."""
    return digest("processing", __version__, image_hash, ground_truth_digest, mode,
                  json.dumps(repr(processing)))
