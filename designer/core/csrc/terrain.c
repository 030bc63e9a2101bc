/* designer.core._cterrain: the terrain's hot loops, compiled.
 *
 * - cast: designer.core.raycast.TerrainRaycaster._march up to its last fallback: each
 *   ray's stretch clipped to the grid's box, the highest terrain and steepest slope over
 *   it (range maxima of per-block maxima), and the sphere-tracing steps over the height
 *   field's bilinear surface;
 * - octave_sum: the value-noise octaves of designer.scene.world_noise.octave_sum.
 *
 * Each computes, ray by ray and point by point, the same IEEE operations in the same
 * order as the numpy code it replaces (compiled without fused multiply-adds), so its
 * results are the numpy code's to the last bit (tests/core/test_compiled_terrain.py keeps
 * that numpy code as its oracle). Arrays come through the buffer protocol
 * (C-contiguous, the dtype each docstring names; the Python callers guarantee both) with
 * their element counts given and checked. Outputs are arrays allocated by the caller.
 * The loops run without the GIL. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>

#include "buffers.h"

/* ------------------------------------------------------------------------- cast */
typedef struct {
    const double *z; /* heights, row-major (ny, nx) */
    Py_ssize_t nx, ny;
    double x0, y0, dx, dy;
} grid_t;

/* The sparse tables of per-block maxima: level (kx, ky) holds, for block (i, j), the
 * maximum over blocks [i, i + 2^ky) x [j, j + 2^kx); stored one after the other, row-major,
 * level (kx, ky) at offset[kx * nky + ky] with ncols[kx] columns. Two tables of the same
 * layout: the highest terrain and the steepest slope. */
typedef struct {
    const double *top, *slope;
    const int64_t *offset, *ncols;
    Py_ssize_t nky;
    Py_ssize_t block, nx, ny; /* block size in cells; the grid's nodes */
} blocks_t;

static inline double clamp(double a, double lo, double hi)
{
    /* np.clip(a, lo, hi) for a finite a */
    a = a < lo ? lo : a;
    return a > hi ? hi : a;
}

/* np.maximum and np.minimum: NaN if either is NaN */
static inline double nmax(double a, double b) { return isnan(a) || isnan(b) ? NAN : (a > b ? a : b); }
static inline double nmin(double a, double b) { return isnan(a) || isnan(b) ? NAN : (a < b ? a : b); }

/* TerrainRaycaster.height: bilinear height at (x, y), clamped to the grid */
static inline double height(const grid_t *g, double x, double y)
{
    double fx = clamp((x - g->x0) / g->dx, 0.0, (double)(g->nx - 1));
    double fy = clamp((y - g->y0) / g->dy, 0.0, (double)(g->ny - 1));
    Py_ssize_t j = (Py_ssize_t)fx, i = (Py_ssize_t)fy;
    if (j > g->nx - 2)
        j = g->nx - 2;
    if (i > g->ny - 2)
        i = g->ny - 2;
    double tx = fx - (double)j, ty = fy - (double)i;
    Py_ssize_t k = i * g->nx + j;
    double z00 = g->z[k], z01 = g->z[k + 1];
    double z10 = g->z[k + g->nx], z11 = g->z[k + g->nx + 1];
    double lower = z00 + tx * (z01 - z00);
    return lower + ty * (z10 + tx * (z11 - z10) - lower);
}

/* the grid cell column (or row) of x, clamped to [0, n - 2] */
static inline Py_ssize_t cell(double x, double x0, double dx, Py_ssize_t n)
{
    return (Py_ssize_t)clamp(floor((x - x0) / dx), 0.0, (double)(n - 2));
}

static inline int floor_log2(Py_ssize_t n)
{
    int k = 0;
    while (n > 1) {
        n >>= 1;
        k++;
    }
    return k;
}

/* the maxima over the inclusive block ranges [i0, i1] x [j0, j1] of both tables: the
 * largest power-of-two levels that fit, four overlapping looks each */
static inline void range_max(const blocks_t *b, Py_ssize_t i0, Py_ssize_t i1, Py_ssize_t j0,
                             Py_ssize_t j1, double *top, double *slope)
{
    int ky = floor_log2(i1 - i0 + 1), kx = floor_log2(j1 - j0 + 1);
    int64_t base = b->offset[kx * b->nky + ky], w = b->ncols[kx];
    Py_ssize_t i2 = i1 - ((Py_ssize_t)1 << ky) + 1, j2 = j1 - ((Py_ssize_t)1 << kx) + 1;
    int64_t ac = base + i0 * w + j0, ae = base + i0 * w + j2;
    int64_t bc = base + i2 * w + j0, be = base + i2 * w + j2;
    *top = nmax(nmax(b->top[ac], b->top[ae]), nmax(b->top[bc], b->top[be]));
    *slope = nmax(nmax(b->slope[ac], b->slope[ae]), nmax(b->slope[bc], b->slope[be]));
}

/* Each ray r (origin org[r], unit direction d[r]) over [t[r], t1[r]]: clipped to the box
 * (x0, x1, y0, y1) and below z_top; where something is left, the highest terrain and
 * steepest slope over the box its stretch spans narrow it to where it is not above that
 * terrain and give its rate; then up to max_iter steps
 * from t[r]: hit[r] = t where the gap first is <= touch (left as the caller set it, NaN,
 * otherwise); going[r] = 1 with t[r] its parameter when the ray still goes after
 * max_iter steps (t1[r] is then its stretch's end). */
static void cast(const grid_t *g, const blocks_t *b, const double box[4], double z_top,
                 const double *org, const double *d, double *t, double *t1, Py_ssize_t n,
                 double touch, double min_step, long max_iter, double *hit, uint8_t *going)
{
    const double lo_axis[3] = {box[0], box[2], -INFINITY};
    const double hi_axis[3] = {box[1], box[3], z_top};
    const double pad_x = 1e-6 * g->dx, pad_y = 1e-6 * g->dy;
    for (Py_ssize_t r = 0; r < n; r++) {
        const double *o = org + 3 * r, *v = d + 3 * r;
        double t0 = t[r], end = t1[r];
        going[r] = 0;
        for (int axis = 0; axis < 3; axis++) {
            double lo = lo_axis[axis], hi = hi_axis[axis], oa = o[axis], va = v[axis];
            if (va == 0) {
                int inside = oa >= lo && oa <= hi;
                t0 = inside ? t0 : INFINITY;
                end = inside ? end : -INFINITY;
            } else {
                double ta = (lo - oa) / va, tb = (hi - oa) / va;
                t0 = nmax(t0, nmin(ta, tb));
                end = nmin(end, nmax(ta, tb));
            }
        }
        if (!(t0 <= end))
            continue;
        /* the terrain's highest point and steepest slope over the ray's stretch */
        double tb = isfinite(end) ? end : t0;
        double ax = o[0] + t0 * v[0], ay = o[1] + t0 * v[1];
        double bx = o[0] + tb * v[0], by = o[1] + tb * v[1];
        double lox = nmin(ax, bx), hix = nmax(ax, bx), loy = nmin(ay, by), hiy = nmax(ay, by);
        Py_ssize_t j0 = cell(lox - pad_x, g->x0, g->dx, g->nx) / b->block;
        Py_ssize_t j1 = cell(hix + pad_x, g->x0, g->dx, g->nx) / b->block;
        Py_ssize_t i0 = cell(loy - pad_y, g->y0, g->dy, g->ny) / b->block;
        Py_ssize_t i1 = cell(hiy + pad_y, g->y0, g->dy, g->ny) / b->block;
        double zmax, slope;
        range_max(b, i0, i1, j0, j1, &zmax, &slope);
        double dz = v[2];
        double t_top = (zmax - o[2]) / dz;
        if (dz < 0)
            t0 = nmax(t0, t_top);
        if (dz > 0)
            end = nmin(end, t_top);
        if (dz == 0 && o[2] > zmax)
            end = -INFINITY;
        double rate = -dz + slope * hypot(v[0], v[1]);
        if (!(t0 <= end))
            continue;
        double tr = t0;
        int live = 1;
        for (long it = 0; it < max_iter && live; it++) {
            double px = o[0] + tr * v[0], py = o[1] + tr * v[1], pz = o[2] + tr * v[2];
            double gap = pz - height(g, px, py);
            if (gap <= touch) {
                hit[r] = tr;
                live = 0;
                break;
            }
            if (!(rate > 0) || !(tr < end)) {
                live = 0;
                break;
            }
            double step = gap / rate;
            step = step > min_step ? step : min_step;
            double next = tr + step;
            tr = next < end ? next : end;
        }
        going[r] = (uint8_t)live;
        t[r] = tr;
        t1[r] = end;
    }
}

static PyObject *py_cast(PyObject *self, PyObject *args)
{
    Py_buffer v[11] = {{0}};
    Py_ssize_t n, nx, ny, block, nkx, nky, table_size;
    double x0, y0, dx, dy, bx0, bx1, by0, by1, z_top, touch, min_step;
    long max_iter;
    if (!PyArg_ParseTuple(args, "y*nndddd" "y*y*y*y*nnnndddd" "d" "y*y*w*w*ddlw*w*", &v[0],
                          &nx, &ny, &x0, &y0, &dx, &dy, &v[1], &v[2], &v[3], &v[4], &block,
                          &nkx, &nky, &table_size, &bx0, &bx1, &by0, &by1, &z_top, &v[5],
                          &v[6], &v[7], &v[8], &touch, &min_step, &max_iter, &v[9], &v[10]))
        return NULL;
    PyObject *result = NULL;
    n = v[7].len / (Py_ssize_t)sizeof(double);
    if (nx >= 2 && ny >= 2 && block >= 1 && nkx >= 1 && nky >= 1
        && sized(&v[0], nx * ny, sizeof(double), "heights")
        && sized(&v[1], table_size, sizeof(double), "top")
        && sized(&v[2], table_size, sizeof(double), "slope")
        && sized(&v[3], nkx * nky, sizeof(int64_t), "offset")
        && sized(&v[4], nkx, sizeof(int64_t), "ncols")
        && sized(&v[5], 3 * n, sizeof(double), "origins")
        && sized(&v[6], 3 * n, sizeof(double), "directions")
        && sized(&v[8], n, sizeof(double), "t1")
        && sized(&v[9], n, sizeof(double), "hit") && sized(&v[10], n, 1, "going")) {
        grid_t g = {v[0].buf, nx, ny, x0, y0, dx, dy};
        blocks_t b = {v[1].buf, v[2].buf, v[3].buf, v[4].buf, nky, block, nx, ny};
        const double box[4] = {bx0, bx1, by0, by1};
        Py_BEGIN_ALLOW_THREADS
        cast(&g, &b, box, z_top, v[5].buf, v[6].buf, v[7].buf, v[8].buf, n, touch, min_step,
             max_iter, v[9].buf, v[10].buf);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    } else if (!PyErr_Occurred()) {
        PyErr_SetString(PyExc_ValueError, "heights: a grid needs at least 2 x 2 nodes");
    }
    release(v, 11);
    return result;
}

/* -------------------------------------------------------------------- octave_sum */
static inline uint64_t splitmix64(uint64_t z)
{
    z += UINT64_C(0x9E3779B97F4A7C15);
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

static inline double unit(uint64_t h) { return (double)(h >> 11) * (2.0 / 9007199254740992.0) - 1.0; }

static inline double quintic(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

/* octave k: keys[k] (the lattice hash key), spacing[k], offset (ox, oy)[k], turn
 * (cos, sin)[k] when rotate, amplitude[k]; total[p] += amplitude * value, k ascending */
static void octave_sum(const double *x, const double *y, Py_ssize_t n, const uint64_t *keys,
                       const double *spacing, const double *offset, const double *turn,
                       const double *amplitude, Py_ssize_t octaves, int rotate, double *total)
{
    for (Py_ssize_t p = 0; p < n; p++) {
        double sum = total[p];
        for (Py_ssize_t k = 0; k < octaves; k++) {
            double u = x[p], w = y[p];
            if (rotate) {
                double c = turn[2 * k], s = turn[2 * k + 1];
                u = c * x[p] - s * y[p];
                w = s * x[p] + c * y[p];
            }
            double gx = (u + offset[2 * k]) / spacing[k];
            double gy = (w + offset[2 * k + 1]) / spacing[k];
            double ixf = floor(gx), iyf = floor(gy);
            double fx = quintic(gx - ixf), fy = quintic(gy - iyf);
            uint64_t ix = (uint64_t)(int64_t)ixf, iy = (uint64_t)(int64_t)iyf, key = keys[k];
            double v00 = unit(splitmix64(splitmix64(key + ix) + iy));
            double v10 = unit(splitmix64(splitmix64(key + ix + 1) + iy));
            double v01 = unit(splitmix64(splitmix64(key + ix) + iy + 1));
            double v11 = unit(splitmix64(splitmix64(key + ix + 1) + iy + 1));
            double top = v00 + (v10 - v00) * fx;
            double bottom = v01 + (v11 - v01) * fx;
            sum += amplitude[k] * (top + (bottom - top) * fy);
        }
        total[p] = sum;
    }
}

static PyObject *py_octave_sum(PyObject *self, PyObject *args)
{
    Py_buffer v[8] = {{0}};
    Py_ssize_t n, octaves;
    int rotate;
    if (!PyArg_ParseTuple(args, "y*y*ny*y*y*y*y*npw*", &v[0], &v[1], &n, &v[2], &v[3], &v[4],
                          &v[5], &v[6], &octaves, &rotate, &v[7]))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], n, sizeof(double), "x") && sized(&v[1], n, sizeof(double), "y")
        && sized(&v[2], octaves, sizeof(uint64_t), "keys")
        && sized(&v[3], octaves, sizeof(double), "spacing")
        && sized(&v[4], 2 * octaves, sizeof(double), "offset")
        && sized(&v[5], 2 * octaves, sizeof(double), "turn")
        && sized(&v[6], octaves, sizeof(double), "amplitude")
        && sized(&v[7], n, sizeof(double), "total")) {
        Py_BEGIN_ALLOW_THREADS
        octave_sum(v[0].buf, v[1].buf, n, v[2].buf, v[3].buf, v[4].buf, v[5].buf, v[6].buf,
                   octaves, rotate, v[7].buf);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    }
    release(v, 8);
    return result;
}

static PyMethodDef methods[] = {
    {"cast", py_cast, METH_VARARGS,
     "cast(heights f8 (ny,nx), nx, ny, x0, y0, dx, dy, top f8, slope f8, offset i8 (kx*ky,), "
     "ncols i8 (kx,), block, kx, ky, table_size, box_x0, box_x1, box_y0, box_y1, z_top, "
     "origins f8 (n,3), directions f8 (n,3), t f8 (n,) in/out, t1 f8 (n,) in/out, touch_m, "
     "min_step_m, max_iter, hit f8 (n,) out, going u1 (n,) out)"},
    {"octave_sum", py_octave_sum, METH_VARARGS,
     "octave_sum(x f8 (n,), y f8 (n,), n, keys u8 (k,), spacing f8 (k,), offset f8 (k,2), "
     "turn f8 (k,2), amplitude f8 (k,), k, rotate, total f8 (n,) in/out)"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_cterrain",
    "The terrain's compiled loops (see designer/core/csrc/terrain.c).", -1, methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__cterrain(void) { return PyModule_Create(&module); }
