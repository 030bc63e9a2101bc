"""Brute-force references for the evaluation tests (plain numpy, no shortcuts)."""

import numpy as np


def _segment(p, a, b):
    e = b - a
    den = e @ e
    t = 0.0 if den == 0 else float(np.clip((p - a) @ e / den, 0.0, 1.0))
    return np.linalg.norm(p - (a + t * e))


def point_triangle_distance(p, a, b, c) -> float:
    """Exact distance from p to triangle abc: the plane foot if inside, else the edges."""
    best = min(_segment(p, a, b), _segment(p, b, c), _segment(p, c, a))
    n = np.cross(b - a, c - a)
    nn = n @ n
    # a plane only where the triangle has one: a (near-)degenerate triangle is its edges
    # to within its width, far below the tests' tolerance
    if nn > 1e-20 * ((b - a) @ (b - a)) * ((c - a) @ (c - a)):
        q = p - ((p - a) @ n) / nn * n
        v0, v1, v2 = b - a, c - a, q - a
        d00, d01, d11, d20, d21 = v0 @ v0, v0 @ v1, v1 @ v1, v2 @ v0, v2 @ v1
        den = d00 * d11 - d01 * d01
        if den > 0:
            v = (d11 * d20 - d01 * d21) / den
            w = (d00 * d21 - d01 * d20) / den
            if v >= 0 and w >= 0 and v + w <= 1:
                best = min(best, float(np.linalg.norm(p - q)))
    return best


def brute_distances(points, vertices, faces) -> np.ndarray:
    """Unsigned distance (N,) from each point to the nearest triangle (local frames)."""
    centre = vertices.mean(axis=0)
    v = vertices - centre
    return np.array([min(point_triangle_distance(p - centre, *v[f]) for f in faces)
                     for p in points])


def exact_point_triangle_distance(p, a, b, c) -> float:
    """The same distance in exact rational arithmetic (for degenerate triangles, where a
    floating-point plane is meaningless)."""
    from fractions import Fraction

    def vec(v):
        return [Fraction(float(x)) for x in v]

    def dot(u, v):
        return sum(x * y for x, y in zip(u, v, strict=True))

    def sub(u, v):
        return [x - y for x, y in zip(u, v, strict=True)]

    p, a, b, c = vec(p), vec(a), vec(b), vec(c)

    def seg2(u, v):
        e = sub(v, u)
        den = dot(e, e)
        t = Fraction(0) if den == 0 else min(Fraction(1), max(Fraction(0), dot(sub(p, u), e) / den))
        q = [x + t * y for x, y in zip(u, e, strict=True)]
        return dot(sub(p, q), sub(p, q))

    best = min(seg2(a, b), seg2(b, c), seg2(c, a))
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d00, d01, d11 = dot(ab, ab), dot(ab, ac), dot(ac, ac)
    det = d00 * d11 - d01 * d01
    if det > 0:
        s = (d11 * dot(ab, ap) - d01 * dot(ac, ap)) / det
        t = (d00 * dot(ac, ap) - d01 * dot(ab, ap)) / det
        if s >= 0 and t >= 0 and s + t <= 1:
            r = [x - s * y - t * z for x, y, z in zip(ap, ab, ac, strict=True)]
            best = min(best, dot(r, r))
    return float(best) ** 0.5
