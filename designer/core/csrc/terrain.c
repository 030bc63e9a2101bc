/* designer.core._cterrain: the terrain's two hot loops, compiled.
 *
 * - march: the sphere-tracing steps of designer.survey.raycast.TerrainRaycaster._march
 *   over a height field's bilinear surface;
 * - octave_sum: the value-noise octaves of designer.scene.world_noise.octave_sum.
 *
 * Each computes, ray by ray and point by point, the same IEEE operations in the same
 * order as the numpy code it replaces (compiled without fused multiply-adds), so its
 * results are the numpy code's to the last bit. Arrays come through the buffer protocol
 * (C-contiguous, the dtype each docstring names; the Python callers guarantee both) with
 * their element counts given and checked. Outputs are arrays allocated by the caller.
 * The loops run without the GIL. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>

#include "buffers.h"

/* ------------------------------------------------------------------------- march */
typedef struct {
    const double *z; /* heights, row-major (ny, nx) */
    Py_ssize_t nx, ny;
    double x0, y0, dx, dy;
} grid_t;

static inline double clamp(double a, double lo, double hi)
{
    /* np.clip(a, lo, hi) for a finite a */
    a = a < lo ? lo : a;
    return a > hi ? hi : a;
}

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

/* Up to max_iter steps of each ray from t[r]: hit[r] = t where the gap first is
 * <= touch (left as the caller set it, NaN, otherwise); going[r] = 1 with t[r] its
 * parameter when the ray still goes after max_iter steps. */
static void march(const grid_t *g, const double *org, const double *d, double *t,
                  const double *rate, const double *t1, Py_ssize_t n, double touch,
                  double min_step, long max_iter, double *hit, uint8_t *going)
{
    for (Py_ssize_t r = 0; r < n; r++) {
        const double *o = org + 3 * r, *v = d + 3 * r;
        double tr = t[r], rr = rate[r], end = t1[r];
        int live = 1;
        for (long it = 0; it < max_iter && live; it++) {
            double px = o[0] + tr * v[0], py = o[1] + tr * v[1], pz = o[2] + tr * v[2];
            double gap = pz - height(g, px, py);
            if (gap <= touch) {
                hit[r] = tr;
                live = 0;
                break;
            }
            if (!(rr > 0) || !(tr < end)) {
                live = 0;
                break;
            }
            double step = gap / rr;
            step = step > min_step ? step : min_step;
            double next = tr + step;
            tr = next < end ? next : end;
        }
        going[r] = (uint8_t)live;
        t[r] = tr;
    }
}

static PyObject *py_march(PyObject *self, PyObject *args)
{
    Py_buffer v[8] = {{0}};
    Py_ssize_t n, nx, ny;
    double x0, y0, dx, dy, touch, min_step;
    long max_iter;
    if (!PyArg_ParseTuple(args, "y*nndddd" "y*y*w*y*y*ddlw*w*", &v[0], &nx, &ny, &x0, &y0,
                          &dx, &dy, &v[1], &v[2], &v[3], &v[4], &v[5], &touch, &min_step,
                          &max_iter, &v[6], &v[7]))
        return NULL;
    PyObject *result = NULL;
    n = v[3].len / (Py_ssize_t)sizeof(double);
    if (nx >= 2 && ny >= 2 && sized(&v[0], nx * ny, sizeof(double), "heights")
        && sized(&v[1], 3 * n, sizeof(double), "origins")
        && sized(&v[2], 3 * n, sizeof(double), "directions")
        && sized(&v[4], n, sizeof(double), "rate") && sized(&v[5], n, sizeof(double), "t1")
        && sized(&v[6], n, sizeof(double), "hit") && sized(&v[7], n, 1, "going")) {
        grid_t g = {v[0].buf, nx, ny, x0, y0, dx, dy};
        Py_BEGIN_ALLOW_THREADS
        march(&g, v[1].buf, v[2].buf, v[3].buf, v[4].buf, v[5].buf, n, touch, min_step,
              max_iter, v[6].buf, v[7].buf);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    } else if (!PyErr_Occurred()) {
        PyErr_SetString(PyExc_ValueError, "heights: a grid needs at least 2 x 2 nodes");
    }
    release(v, 8);
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
    {"march", py_march, METH_VARARGS,
     "march(heights f8 (ny,nx), nx, ny, x0, y0, dx, dy, origins f8 (n,3), directions f8 "
     "(n,3), t f8 (n,) in/out, rate f8 (n,), t1 f8 (n,), touch_m, min_step_m, max_iter, "
     "hit f8 (n,) out, going u1 (n,) out)"},
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
