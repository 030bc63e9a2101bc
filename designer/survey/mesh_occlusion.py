"""Sight lines blocked by triangle meshes (buildings) as well as by the terrain.

World frame X east, Y north, Z up (m). :class:`MeshOccluder` tests the segment from a
camera centre to a point against every triangle (Möller–Trumbore, vectorised over
segments × triangles in batches); a segment is blocked when it meets a triangle
strictly between the camera and ``tol_m`` before the point. Scenes hold tens of
buildings (hundreds of triangles), so brute force is enough; a triangle whose bounding
box the segment's box misses is skipped. :class:`OccluderStack` answers for the
terrain ray caster and the meshes together, with the interface
:func:`designer.survey.visibility.visible_pairs` asks of a ray caster.
"""

from __future__ import annotations

import numpy as np

#: segment × triangle pairs tested in one vectorised batch
PAIR_BATCH = 1 << 20


class MeshOccluder:
    """Triangles ``vertices_world`` (N, 3), ``faces`` (M, 3) that block sight lines."""

    def __init__(self, vertices_world: np.ndarray, faces: np.ndarray) -> None:
        v = np.asarray(vertices_world, float).reshape(-1, 3)
        f = np.asarray(faces, np.int64).reshape(-1, 3)
        # relative to one reference point: UTM-sized coordinates keep their precision
        self._ref = v.mean(axis=0) if len(v) else np.zeros(3)
        tri = v[f] - self._ref
        self._a = tri[:, 0]
        self._e1 = tri[:, 1] - tri[:, 0]
        self._e2 = tri[:, 2] - tri[:, 0]
        self._lo, self._hi = tri.min(axis=1), tri.max(axis=1)
        self.z_min_m = float(v[:, 2].min()) if len(v) else np.inf
        self.z_max_m = float(v[:, 2].max()) if len(v) else -np.inf

    def occluded(self, points_world, cameras_world, tol_m: float = 0.01) -> np.ndarray:
        """(K,) True where the segment camera → point is blocked by a triangle."""
        P = np.asarray(points_world, float).reshape(-1, 3) - self._ref
        C = np.asarray(cameras_world, float).reshape(-1, 3) - self._ref
        out = np.zeros(len(P), bool)
        if not len(self._a) or not len(P):
            return out
        seg_lo, seg_hi = np.minimum(P, C), np.maximum(P, C)
        near = ((seg_lo[:, None, :] <= self._hi[None]) & (seg_hi[:, None, :] >= self._lo[None])
                ).all(axis=2)
        k, t = np.nonzero(near)
        for start in range(0, len(k), PAIR_BATCH):
            kk, tt = k[start:start + PAIR_BATCH], t[start:start + PAIR_BATCH]
            hit = _segment_hits(C[kk], P[kk], self._a[tt], self._e1[tt], self._e2[tt], tol_m)
            out[kk[hit]] = True
        return out


def _segment_hits(C, P, a, e1, e2, tol_m: float) -> np.ndarray:
    """Möller–Trumbore: does the segment C → P meet triangle (a, a + e1, a + e2) at a
    distance from C between 0 and |P − C| − tol_m?"""
    d = P - C
    length = np.linalg.norm(d, axis=1)
    d = d / np.maximum(length, 1e-300)[:, None]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = np.divide(1.0, det, out=np.zeros_like(det), where=ok)
    s = C - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = np.einsum("ij,ij->i", d, q) * inv
    dist = np.einsum("ij,ij->i", e2, q) * inv
    return ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (dist > 0) & (dist < length - tol_m)


class OccluderStack:
    """The terrain ray caster (or None) and mesh occluders as one occluder."""

    def __init__(self, terrain, meshes: list[MeshOccluder]) -> None:
        self.terrain, self.meshes = terrain, list(meshes)
        parts = ([terrain] if terrain is not None else []) + self.meshes
        self.z_min_m = min(p.z_min_m for p in parts)
        self.z_max_m = max(p.z_max_m for p in parts)

    def occluded(self, points_world, cameras_world, tol_m: float = 0.01) -> np.ndarray:
        hidden = (np.zeros(len(np.asarray(points_world).reshape(-1, 3)), bool)
                  if self.terrain is None
                  else np.asarray(self.terrain.occluded(points_world, cameras_world, tol_m=tol_m)))
        for mesh in self.meshes:
            left = ~hidden
            if left.any():
                P = np.asarray(points_world, float).reshape(-1, 3)[left]
                C = np.asarray(cameras_world, float).reshape(-1, 3)[left]
                hidden[np.flatnonzero(left)] = mesh.occluded(P, C, tol_m=tol_m)
        return hidden
