/* posekit.geometry._accel: optional compiled batch kernels of posekit.geometry.
 *
 * quat_to_matrix(q, out): the rotation matrices of an (N, 4) C-contiguous float64 array of
 * (x, y, z, w) rows into an (N, 3, 3) C-contiguous float64 array, with exactly the IEEE
 * operations of the numpy kernel posekit.geometry._batch.to_matrix_numpy, in the same order
 * (the build turns off floating-point contraction); tests/geometry/test_accel.py compares
 * the two bit for bit. Buffers come through the buffer protocol: no numpy headers needed.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

static int
get_doubles(PyObject *obj, Py_buffer *view, int writable, const char *what)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0)
        return -1;
    if (view->itemsize != 8 || view->format == NULL || strcmp(view->format, "d") != 0) {
        PyBuffer_Release(view);
        PyErr_Format(PyExc_TypeError, "%s must be float64", what);
        return -1;
    }
    return 0;
}

static PyObject *
quat_to_matrix(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    Py_buffer qv, mv;
    Py_ssize_t n, i;
    const double sqrt2 = 1.4142135623730951; /* 2.0 ** 0.5 */
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "quat_to_matrix(q, out)");
        return NULL;
    }
    if (get_doubles(args[0], &qv, 0, "q") < 0)
        return NULL;
    if (get_doubles(args[1], &mv, 1, "out") < 0) {
        PyBuffer_Release(&qv);
        return NULL;
    }
    n = qv.len / (4 * 8);
    if (qv.len != n * 4 * 8 || mv.len != n * 9 * 8) {
        PyBuffer_Release(&qv);
        PyBuffer_Release(&mv);
        PyErr_SetString(PyExc_ValueError, "q must be (N, 4) and out (N, 3, 3)");
        return NULL;
    }
    {
        const double *q = (const double *)qv.buf;
        double *m = (double *)mv.buf;
        Py_BEGIN_ALLOW_THREADS
        for (i = 0; i < n; i++, q += 4, m += 9) {
            double x = q[0] * sqrt2, y = q[1] * sqrt2, z = q[2] * sqrt2, w = q[3] * sqrt2;
            double xx = x * x, yy = y * y, zz = z * z;
            double xy = x * y, xz = x * z, yz = y * z;
            double wx = w * x, wy = w * y, wz = w * z;
            m[0] = 1.0 - (yy + zz);
            m[1] = xy - wz;
            m[2] = xz + wy;
            m[3] = xy + wz;
            m[4] = 1.0 - (xx + zz);
            m[5] = yz - wx;
            m[6] = xz - wy;
            m[7] = yz + wx;
            m[8] = 1.0 - (xx + yy);
        }
        Py_END_ALLOW_THREADS
    }
    PyBuffer_Release(&qv);
    PyBuffer_Release(&mv);
    Py_RETURN_NONE;
}

static PyMethodDef accel_methods[] = {
    {"quat_to_matrix", (PyCFunction)(void (*)(void))quat_to_matrix, METH_FASTCALL,
     "quat_to_matrix(q, out): (N, 3, 3) rotation matrices of (N, 4) xyzw rows, into out."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef accel_module = {
    PyModuleDef_HEAD_INIT, "posekit.geometry._accel",
    "Compiled batch kernels of posekit.geometry (see posekit.geometry._batch).", -1,
    accel_methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC
PyInit__accel(void)
{
    return PyModule_Create(&accel_module);
}
