/* Closest point on a triangle, and which feature of it is nearest.
 *
 * Local coordinates (world - a mesh origin), double, metres. Follows Ericson,
 * Real-Time Collision Detection (2005), section 5.1.5, with every division guarded;
 * triangles too thin for a trustworthy plane (sin of the angle at the first corner
 * below 1e-10) are handled as their three edges. The feature (the face, edge k joining
 * corners k and k + 1, or corner k) tells the query which pseudo-normal gives the sign.
 * A triangle is 9 doubles: corners a, b, c, each x, y, z. */
#ifndef DESIGNER_CLOSEST_H
#define DESIGNER_CLOSEST_H

#include <math.h>

enum { FACE = 0, EDGE0 = 1, EDGE1 = 2, EDGE2 = 3, VERT0 = 4, VERT1 = 5, VERT2 = 6 };

#define SLIVER 1e-20

typedef struct {
    double d2;      /* squared distance */
    double q[3];    /* the nearest point */
    int feature;
} closest_t;

static inline double seg_param(double num, double den)
{
    if (den <= 0.0)
        return 0.0;
    double t = num / den;
    t = t > 0.0 ? t : 0.0;
    return t < 1.0 ? t : 1.0;
}

static inline double sq(double v) { return v * v; }

static inline closest_t point_at(double px, double py, double pz, double qx, double qy,
                                 double qz, int feature)
{
    closest_t r = {sq(px - qx) + sq(py - qy) + sq(pz - qz), {qx, qy, qz}, feature};
    return r;
}

/* the three edges of a (near-)degenerate triangle */
static closest_t closest_degenerate(double px, double py, double pz, const double *tri)
{
    closest_t best = {INFINITY, {0.0, 0.0, 0.0}, EDGE0};
    for (int k = 0; k < 3; k++) {
        const double *a = tri + 3 * k, *b = tri + 3 * ((k + 1) % 3);
        double ex = b[0] - a[0], ey = b[1] - a[1], ez = b[2] - a[2];
        double t = seg_param((px - a[0]) * ex + (py - a[1]) * ey + (pz - a[2]) * ez,
                             ex * ex + ey * ey + ez * ez);
        double qx = a[0] + t * ex, qy = a[1] + t * ey, qz = a[2] + t * ez;
        double d2 = sq(px - qx) + sq(py - qy) + sq(pz - qz);
        if (d2 < best.d2) {
            best.d2 = d2;
            best.q[0] = qx, best.q[1] = qy, best.q[2] = qz;
            best.feature = t == 0.0 ? VERT0 + k : (t == 1.0 ? VERT0 + (k + 1) % 3 : EDGE0 + k);
        }
    }
    return best;
}

static inline closest_t closest_point(double px, double py, double pz, const double *tri)
{
    double ax = tri[0], ay = tri[1], az = tri[2];
    double abx = tri[3] - ax, aby = tri[4] - ay, abz = tri[5] - az;
    double acx = tri[6] - ax, acy = tri[7] - ay, acz = tri[8] - az;
    /* Ericson's region tests assume a proper triangle: (near-)degenerate ones
     * (|ab x ac|^2 tiny against |ab|^2 |ac|^2) go to the edge-only routine. */
    double nx = aby * acz - abz * acy, ny = abz * acx - abx * acz, nz = abx * acy - aby * acx;
    if (!(nx * nx + ny * ny + nz * nz > SLIVER * ((abx * abx + aby * aby + abz * abz)
                                                 * (acx * acx + acy * acy + acz * acz))))
        return closest_degenerate(px, py, pz, tri);
    double apx = px - ax, apy = py - ay, apz = pz - az;
    double d1 = abx * apx + aby * apy + abz * apz;
    double d2 = acx * apx + acy * apy + acz * apz;
    if (d1 <= 0.0 && d2 <= 0.0)
        return point_at(px, py, pz, ax, ay, az, VERT0);
    double bpx = px - tri[3], bpy = py - tri[4], bpz = pz - tri[5];
    double d3 = abx * bpx + aby * bpy + abz * bpz;
    double d4 = acx * bpx + acy * bpy + acz * bpz;
    if (d3 >= 0.0 && d4 <= d3)
        return point_at(px, py, pz, tri[3], tri[4], tri[5], VERT1);
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        double v = seg_param(d1, d1 - d3);
        return point_at(px, py, pz, ax + v * abx, ay + v * aby, az + v * abz, EDGE0);
    }
    double cpx = px - tri[6], cpy = py - tri[7], cpz = pz - tri[8];
    double d5 = abx * cpx + aby * cpy + abz * cpz;
    double d6 = acx * cpx + acy * cpy + acz * cpz;
    if (d6 >= 0.0 && d5 <= d6)
        return point_at(px, py, pz, tri[6], tri[7], tri[8], VERT2);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        double w = seg_param(d2, d2 - d6);
        return point_at(px, py, pz, ax + w * acx, ay + w * acy, az + w * acz, EDGE2);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        double w = seg_param(d4 - d3, (d4 - d3) + (d5 - d6));
        return point_at(px, py, pz, tri[3] + w * (tri[6] - tri[3]), tri[4] + w * (tri[7] - tri[4]),
                        tri[5] + w * (tri[8] - tri[5]), EDGE1);
    }
    double den = va + vb + vc; /* = |ab x ac|^2 > 0 here */
    double v = vb / den, w = vc / den;
    return point_at(px, py, pz, ax + abx * v + acx * w, ay + aby * v + acy * w,
                    az + abz * v + acz * w, FACE);
}

#endif
