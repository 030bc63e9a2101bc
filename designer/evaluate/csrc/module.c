/* designer.evaluate._ckernels: the comparison's kernels for Python.
 *
 * Every argument array is passed through the buffer protocol (C-contiguous, the dtype
 * the docstring names; the Python wrappers in designer.evaluate guarantee both), with
 * its element counts given explicitly and checked against the buffer sizes. Outputs are
 * arrays allocated by the caller. Long loops run without the GIL. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdlib.h>

#include "buffers.h"
#include "kernels.h"

#define D sizeof(double)
#define I sizeof(int64_t)

static PyObject *py_centroid_codes(PyObject *self, PyObject *args)
{
    Py_buffer v[5] = {{0}};
    Py_ssize_t nv, m;
    int threads;
    if (!PyArg_ParseTuple(args, "y*ny*ny*y*w*i", &v[0], &nv, &v[1], &m, &v[2], &v[3], &v[4],
                          &threads))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], 3 * nv, D, "local") && sized(&v[1], 3 * m, I, "faces")
        && sized(&v[2], 3, D, "lo") && sized(&v[3], 3, D, "scale") && sized(&v[4], m, I, "out")) {
        Py_BEGIN_ALLOW_THREADS
        centroid_codes(v[0].buf, v[1].buf, m, v[2].buf, v[3].buf, v[4].buf, threads);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    }
    release(v, 5);
    return result;
}

static PyObject *py_radix_argsort(PyObject *self, PyObject *args)
{
    Py_buffer v[2] = {{0}};
    Py_ssize_t n;
    if (!PyArg_ParseTuple(args, "y*nw*", &v[0], &n, &v[1]))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], n, I, "codes") && sized(&v[1], n, I, "order")) {
        int status;
        Py_BEGIN_ALLOW_THREADS
        status = radix_argsort(v[0].buf, n, v[1].buf);
        Py_END_ALLOW_THREADS
        result = status == 0 ? Py_NewRef(Py_None) : PyErr_NoMemory();
    }
    release(v, 2);
    return result;
}

static PyObject *py_build_bvh(PyObject *self, PyObject *args)
{
    Py_buffer v[4] = {{0}};
    Py_ssize_t m;
    if (!PyArg_ParseTuple(args, "y*y*nw*w*", &v[0], &v[1], &m, &v[2], &v[3]))
        return NULL;
    PyObject *result = NULL;
    Py_ssize_t cap = m > 0 ? 2 * m - 1 : 1;
    if (sized(&v[0], m, I, "codes") && sized(&v[1], 9 * m, D, "tri")
        && sized(&v[2], 6 * cap, D, "box") && sized(&v[3], 2 * cap, I, "link")) {
        int64_t n_nodes;
        Py_BEGIN_ALLOW_THREADS
        n_nodes = build_bvh(v[0].buf, v[1].buf, m, v[2].buf, v[3].buf);
        Py_END_ALLOW_THREADS
        if (n_nodes == -2)
            PyErr_NoMemory();
        else if (n_nodes < 0)
            PyErr_SetString(PyExc_RuntimeError, "bounding-volume hierarchy deeper than 256");
        else
            result = PyLong_FromLongLong(n_nodes);
    }
    release(v, 4);
    return result;
}

static PyObject *py_query(PyObject *self, PyObject *args)
{
    /* nearest may be None */
    Py_buffer v[14] = {{0}};
    Py_ssize_t n, m, k, e, nv;
    double limit_d2;
    int threads;
    PyObject *nearest_obj;
    if (!PyArg_ParseTuple(args, "y*ny*y*y*y*ny*y*ny*y*y*ny*ny*dw*Oi", &v[0], &n, &v[1], &v[2],
                          &v[3], &v[4], &m, &v[5], &v[6], &k, &v[7], &v[8], &v[9], &e,
                          &v[10], &nv, &v[11], &limit_d2, &v[12], &nearest_obj, &threads))
        return NULL;
    PyObject *result = NULL;
    int64_t *nearest = NULL;
    if (nearest_obj != Py_None) {
        if (PyObject_GetBuffer(nearest_obj, &v[13], PyBUF_WRITABLE | PyBUF_C_CONTIGUOUS) != 0)
            goto done;
        if (!sized(&v[13], n, I, "nearest"))
            goto done;
        nearest = v[13].buf;
    }
    if (sized(&v[0], 3 * n, D, "points") && sized(&v[1], 3, D, "origin")
        && sized(&v[2], 3, D, "lo") && sized(&v[3], 3, D, "scale")
        && sized(&v[4], 9 * m, D, "triangles") && sized(&v[5], 6 * k, D, "box")
        && sized(&v[6], 2 * k, I, "link") && sized(&v[7], 3 * m, D, "normals_face")
        && sized(&v[8], 3 * m, I, "neighbours") && sized(&v[9], 3 * e, D, "crowded")
        && sized(&v[10], 3 * nv, D, "normals_vertex") && sized(&v[11], 3 * m, I, "corner_vertex")
        && sized(&v[12], n, D, "dist")) {
        mesh_index_t mesh = {v[4].buf, v[5].buf, v[6].buf, v[7].buf, v[8].buf, v[9].buf,
                             v[10].buf, v[11].buf};
        int status;
        Py_BEGIN_ALLOW_THREADS
        status = query(v[0].buf, n, v[1].buf, v[2].buf, v[3].buf, &mesh, limit_d2, v[12].buf,
                       nearest, threads);
        Py_END_ALLOW_THREADS
        result = status == 0 ? Py_NewRef(Py_None) : PyErr_NoMemory();
    }
done:
    release(v, 14);
    return result;
}

static PyObject *py_weld_vertices(PyObject *self, PyObject *args)
{
    Py_buffer v[3] = {{0}};
    Py_ssize_t n, m;
    if (!PyArg_ParseTuple(args, "y*ny*nw*", &v[0], &n, &v[1], &m, &v[2]))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], 3 * n, D, "vertices") && sized(&v[1], m, I, "candidates")
        && sized(&v[2], n, I, "out")) {
        Py_BEGIN_ALLOW_THREADS
        weld_vertices(v[0].buf, n, v[1].buf, m, v[2].buf);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    }
    release(v, 3);
    return result;
}

static PyObject *py_face_geometry(PyObject *self, PyObject *args)
{
    Py_buffer v[5] = {{0}};
    Py_ssize_t nv, m;
    int threads;
    if (!PyArg_ParseTuple(args, "y*ny*nw*w*w*i", &v[0], &nv, &v[1], &m, &v[2], &v[3], &v[4],
                          &threads))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], 3 * nv, D, "local") && sized(&v[1], 3 * m, I, "faces")
        && sized(&v[2], 9 * m, D, "tri") && sized(&v[3], 3 * m, D, "normal")
        && sized(&v[4], 3 * m, D, "angle")) {
        Py_BEGIN_ALLOW_THREADS
        face_geometry(v[0].buf, v[1].buf, m, v[2].buf, v[3].buf, v[4].buf, threads);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    }
    release(v, 5);
    return result;
}

static PyObject *py_vertex_normals(PyObject *self, PyObject *args)
{
    Py_buffer v[4] = {{0}};
    Py_ssize_t m, nv;
    if (!PyArg_ParseTuple(args, "y*ny*y*w*n", &v[0], &m, &v[1], &v[2], &v[3], &nv))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], 3 * m, I, "faces") && sized(&v[1], 3 * m, D, "normal")
        && sized(&v[2], 3 * m, D, "angle") && sized(&v[3], 3 * nv, D, "vert")) {
        Py_BEGIN_ALLOW_THREADS
        vertex_normals(v[0].buf, m, v[1].buf, v[2].buf, v[3].buf);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    }
    release(v, 4);
    return result;
}

static PyObject *py_edge_neighbours(PyObject *self, PyObject *args)
{
    /* returns the crowded-edge normal sums as bytes (E * 3 doubles) */
    Py_buffer v[3] = {{0}};
    Py_ssize_t m, nv;
    int threads;
    if (!PyArg_ParseTuple(args, "y*nny*w*i", &v[0], &m, &nv, &v[1], &v[2], &threads))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], 3 * m, I, "faces") && sized(&v[1], 3 * m, D, "normal")
        && sized(&v[2], 3 * m, I, "neighbour")) {
        double *sums = NULL;
        int64_t crowded = 0;
        int status;
        Py_BEGIN_ALLOW_THREADS
        status = edge_neighbours(v[0].buf, m, nv, v[1].buf, v[2].buf, &sums, &crowded, threads);
        Py_END_ALLOW_THREADS
        if (status != 0)
            PyErr_NoMemory();
        else
            result = PyBytes_FromStringAndSize((const char *)sums, 3 * crowded * D);
        free(sums);
    }
    release(v, 3);
    return result;
}

static PyObject *py_nearest_point_grid(PyObject *self, PyObject *args)
{
    Py_buffer v[3] = {{0}};
    Py_ssize_t n, rows, cols;
    double cell, gap;
    int threads;
    if (!PyArg_ParseTuple(args, "y*y*nnnddw*i", &v[0], &v[1], &n, &rows, &cols, &cell, &gap,
                          &v[2], &threads))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], n, D, "x") && sized(&v[1], n, D, "y") && sized(&v[2], rows * cols, I, "out")) {
        int status;
        Py_BEGIN_ALLOW_THREADS
        status = nearest_point_grid(v[0].buf, v[1].buf, n, rows, cols, cell, gap, v[2].buf,
                                    threads);
        Py_END_ALLOW_THREADS
        result = status == 0 ? Py_NewRef(Py_None) : PyErr_NoMemory();
    }
    release(v, 3);
    return result;
}

static PyObject *py_highest_surface(PyObject *self, PyObject *args)
{
    Py_buffer v[4] = {{0}};
    Py_ssize_t nv, m, rows, cols;
    double cell;
    if (!PyArg_ParseTuple(args, "y*y*ny*ndnnw*", &v[0], &v[1], &nv, &v[2], &m, &cell, &rows,
                          &cols, &v[3]))
        return NULL;
    PyObject *result = NULL;
    if (sized(&v[0], 2 * nv, D, "xy_local") && sized(&v[1], nv, D, "z")
        && sized(&v[2], 3 * m, I, "faces") && sized(&v[3], rows * cols, D, "out")) {
        Py_BEGIN_ALLOW_THREADS
        highest_surface(v[0].buf, v[1].buf, v[2].buf, m, cell, rows, cols, v[3].buf);
        Py_END_ALLOW_THREADS
        result = Py_NewRef(Py_None);
    }
    release(v, 4);
    return result;
}

static PyMethodDef methods[] = {
    {"centroid_codes", py_centroid_codes, METH_VARARGS,
     "centroid_codes(local f8 (v,3), v, faces i8 (m,3), m, lo, scale, out u8 (m,), threads)"},
    {"radix_argsort", py_radix_argsort, METH_VARARGS,
     "radix_argsort(codes u8 (n,), n, order i8 (n,)): stable"},
    {"build_bvh", py_build_bvh, METH_VARARGS,
     "build_bvh(codes u8 (m,), tri f8 (m,9), m, box f8 (2m-1,6), link i8 (2m-1,2)) -> nodes"},
    {"query", py_query, METH_VARARGS,
     "query(points_world f8 (n,3), n, origin, lo, scale, tri, m, box, link, k, normals_face, "
     "neighbours, crowded, e, normals_vertex, v, corner_vertex, limit_d2, dist f8 (n,), "
     "nearest i8 (n,) or None, threads)"},
    {"weld_vertices", py_weld_vertices, METH_VARARGS,
     "weld_vertices(vertices f8 (n,3), n, candidates i8 (m,), m, out i8 (n,))"},
    {"face_geometry", py_face_geometry, METH_VARARGS,
     "face_geometry(local f8 (v,3), v, faces i8 (m,3), m, tri (m,9), normal (m,3), "
     "angle (m,3), threads)"},
    {"vertex_normals", py_vertex_normals, METH_VARARGS,
     "vertex_normals(faces i8 (m,3), m, normal, angle, vert f8 (v,3) zeroed, v)"},
    {"edge_neighbours", py_edge_neighbours, METH_VARARGS,
     "edge_neighbours(faces i8 (m,3), m, v, normal f8 (m,3), neighbour i8 (m,3), threads) -> bytes"},
    {"nearest_point_grid", py_nearest_point_grid, METH_VARARGS,
     "nearest_point_grid(x f8 (n,), y f8 (n,), n, rows, cols, cell, gap, out i8, threads)"},
    {"highest_surface", py_highest_surface, METH_VARARGS,
     "highest_surface(xy_local f8 (v,2), z f8 (v,), v, faces i8 (m,3), m, cell, rows, "
     "cols, out f8 (rows, cols) NaN-filled)"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_ckernels",
    "The comparison's compiled kernels (see designer/evaluate/csrc).", -1, methods,
};

PyMODINIT_FUNC PyInit__ckernels(void) { return PyModule_Create(&module); }
