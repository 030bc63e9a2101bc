/* Buffer-protocol helpers shared by designer's compiled modules
 * (designer.evaluate._ckernels, designer.core._cterrain). Include after <Python.h>. */
#ifndef DESIGNER_BUFFERS_H
#define DESIGNER_BUFFERS_H

/* the buffer holds exactly `count` items of `size` bytes (else a ValueError naming it) */
static inline int sized(const Py_buffer *b, Py_ssize_t count, Py_ssize_t size,
                        const char *name)
{
    if (b->len != count * size) {
        PyErr_Format(PyExc_ValueError, "%s: %zd bytes, expected %zd", name, b->len,
                     count * size);
        return 0;
    }
    return 1;
}

/* release the first `n` views (those never filled have obj NULL) */
static inline void release(Py_buffer *views, int n)
{
    for (int k = 0; k < n; k++)
        if (views[k].obj != NULL)
            PyBuffer_Release(&views[k]);
}

#endif
