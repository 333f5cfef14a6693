/* posekit.tf2._accel: optional compiled kernels of the tf2 lookup engine.
 *
 * Each function here computes exactly what its pure-Python counterpart in
 * posekit/tf2/path.py computes: the same IEEE double operations in the same order (the
 * build turns off floating-point contraction, so no fused multiply-add changes a rounding),
 * the same libm calls (sin, acos, sqrt) that Python's math module makes. Wherever Python
 * would raise (a division by zero, sqrt of a negative number) or the inputs leave the common
 * case (a non-float field, a stamp beyond 2**53 ns from its neighbour, a name with a leading
 * '/'), the function returns None and the caller runs the Python code, which then decides.
 * tests/tf2/test_accel.py runs both on the same random inputs and compares bit patterns.
 *
 *   evaluate(mode, src, tgt, check, t) -> (sec, nanosec, qx, qy, qz, qw, vx, vy, vz) | None
 *   sample_from_msg(msg) -> (stamp_ns, parent, child, (qx, qy, qz, qw, tx, ty, tz)) | None
 *   stamped(target, source, result) -> TransformStamped
 *   configure(Time, Header, Vector3, Quaternion, Transform, TransformStamped) -> None
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>
#include <math.h>

#define NS_PER_S 1000000000LL
/* int / int in Python equals double / double when both fit in the mantissa */
#define EXACT_LIMIT (1LL << 53)
/* stamps beyond this are left to Python (no overflow in differences) */
#define STAMP_LIMIT (1LL << 62)

enum { MODE_UP = 0, MODE_DOWN = 1, MODE_FULL = 2 };

/* result of a helper: OK, FALLBACK (the caller returns None), or ERROR (Python exception set) */
enum { ERROR = -1, FALLBACK = 0, OK = 1 };

static PyObject *s_parent, *s_sample, *s_transform, *s_translation, *s_rotation, *s_header,
    *s_stamp, *s_frame_id, *s_child_frame_id, *s_sec, *s_nanosec, *s_x, *s_y, *s_z, *s_w;

/* ---------------------------------------------------------------------------------------- */
/* reading Python values                                                                     */
/* ---------------------------------------------------------------------------------------- */

static int
read_ll(PyObject *o, long long *out)
{
    int overflow;
    long long v;
    if (!PyLong_CheckExact(o))
        return FALLBACK;
    v = PyLong_AsLongLongAndOverflow(o, &overflow);
    if (overflow || (v == -1 && PyErr_Occurred())) {
        PyErr_Clear();
        return FALLBACK;
    }
    if (v >= STAMP_LIMIT || v <= -STAMP_LIMIT)
        return FALLBACK;
    *out = v;
    return OK;
}

/* a 7-tuple of exact floats */
static int
read7(PyObject *tup, double *o)
{
    Py_ssize_t i;
    if (!PyTuple_Check(tup) || PyTuple_GET_SIZE(tup) != 7)
        return FALLBACK;
    for (i = 0; i < 7; i++) {
        PyObject *f = PyTuple_GET_ITEM(tup, i);
        if (!PyFloat_CheckExact(f))
            return FALLBACK;
        o[i] = PyFloat_AS_DOUBLE(f);
    }
    return OK;
}

static int
list_ll(PyObject *list, Py_ssize_t i, long long *out)
{
    return read_ll(PyList_GET_ITEM(list, i), out);
}

/* a new tuple of n floats (NULL with an exception on failure) */
static PyObject *
float_tuple(const double *v, Py_ssize_t n)
{
    PyObject *t = PyTuple_New(n), *f;
    Py_ssize_t k;
    if (t == NULL)
        return NULL;
    for (k = 0; k < n; k++) {
        f = PyFloat_FromDouble(v[k]);
        if (f == NULL) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SET_ITEM(t, k, f);
    }
    return t;
}

/* ---------------------------------------------------------------------------------------- */
/* kernels (Python: posekit.tf2.path)                                                        */
/* ---------------------------------------------------------------------------------------- */

/* slerp_terms: (angle, 1/sin(angle) or 0, flip); FALLBACK where Python would raise */
static int
slerp_terms(const double *a, const double *b, double *theta, double *d, int *flip)
{
    double x1 = a[0], y1 = a[1], z1 = a[2], w1 = a[3];
    double x2 = b[0], y2 = b[1], z2 = b[2], w2 = b[3];
    double dot = x1 * x2 + y1 * y2 + z1 * z2 + w1 * w2;
    double den = sqrt((x1 * x1 + y1 * y1 + z1 * z1 + w1 * w1)
                      * (x2 * x2 + y2 * y2 + z2 * z2 + w2 * w2));
    double c, th, sn;
    if (den == 0.0)
        return FALLBACK;
    c = (dot < 0.0 ? -dot : dot) / den;
    th = acos(c < -1.0 ? -1.0 : (c > 1.0 ? 1.0 : c));
    if (th != 0.0) {
        sn = sin(th);
        if (sn == 0.0)
            return FALLBACK;
        *d = 1.0 / sn;
    }
    else {
        *d = 0.0;
    }
    *theta = th;
    *flip = dot < 0.0;
    return OK;
}

/* acc := e (first) or accumulate(e, acc): v = quatRotate(q_e, v) + t_e, q = q_e * q */
static void
accumulate(const double *e, double *acc)
{
    double qx = e[0], qy = e[1], qz = e[2], qw = e[3];
    double ex = e[4], ey = e[5], ez = e[6];
    double sqx = acc[0], sqy = acc[1], sqz = acc[2], sqw = acc[3];
    double sx = acc[4], sy = acc[5], sz = acc[6];
    double px = qw * sx + qy * sz - qz * sy;
    double py = qw * sy + qz * sx - qx * sz;
    double pz = qw * sz + qx * sy - qy * sx;
    double pw = -qx * sx - qy * sy - qz * sz;
    acc[4] = px * qw - pw * qx - py * qz + pz * qy + ex;
    acc[5] = py * qw - pw * qy - pz * qx + px * qz + ey;
    acc[6] = pz * qw - pw * qz - px * qy + py * qx + ez;
    acc[0] = qw * sqx + qx * sqw + qy * sqz - qz * sqy;
    acc[1] = qw * sqy + qy * sqw + qz * sqx - qx * sqz;
    acc[2] = qw * sqz + qz * sqw + qx * sqy - qy * sqx;
    acc[3] = qw * sqw - qx * sqx - qy * sqy - qz * sqz;
}

/* finalize: inv = conj(q_t); v = rotate(inv, v_s) + rotate(inv, -v_t); q = inv * q_s.
 * tgt is the target chain, src the source chain (or NULL: the source is the top). */
static void
inverse_rotate(const double *tgt, const double *src, double *out)
{
    double ix = -tgt[0], iy = -tgt[1], iz = -tgt[2], iw = tgt[3];
    double u[2][3];
    double r[2][3];
    int k;
    u[0][0] = -tgt[4];
    u[0][1] = -tgt[5];
    u[0][2] = -tgt[6];
    u[1][0] = src ? src[4] : 0.0;
    u[1][1] = src ? src[5] : 0.0;
    u[1][2] = src ? src[6] : 0.0;
    for (k = 0; k < 2; k++) {
        double ux = u[k][0], uy = u[k][1], uz = u[k][2];
        double px = iw * ux + iy * uz - iz * uy;
        double py = iw * uy + iz * ux - ix * uz;
        double pz = iw * uz + ix * uy - iy * ux;
        double pw = -ix * ux - iy * uy - iz * uz;
        r[k][0] = px * iw - pw * ix - py * iz + pz * iy;
        r[k][1] = py * iw - pw * iy - pz * ix + px * iz;
        r[k][2] = pz * iw - pw * iz - px * iy + py * ix;
    }
    if (src == NULL) {
        out[0] = ix;
        out[1] = iy;
        out[2] = iz;
        out[3] = iw;
        out[4] = r[0][0];
        out[5] = r[0][1];
        out[6] = r[0][2];
        return;
    }
    {
        double qx = src[0], qy = src[1], qz = src[2], qw = src[3];
        out[0] = iw * qx + ix * qw + iy * qz - iz * qy;
        out[1] = iw * qy + iy * qw + iz * qx - ix * qz;
        out[2] = iw * qz + iz * qw + ix * qy - iy * qx;
        out[3] = iw * qw - ix * qx - iy * qy - iz * qz;
        out[4] = r[1][0] + r[0][0];
        out[5] = r[1][1] + r[0][1];
        out[6] = r[1][2] + r[0][2];
    }
}

/* tf2's Matrix3x3 setRotation + getRotation of q (in place); FALLBACK where Python raises */
static int
canonical(double *q)
{
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double dd = x * x + y * y + z * z + w * w;
    double s, xs, ys, zs, wx, wy, wz, xx, xy, xz, yy, yz, zz, trace, h, arg;
    double m00, m11, m22, m01, m10, m02, m20, m12, m21;
    int i;
    if (dd == 0.0)
        return FALLBACK;
    s = 2.0 / dd;
    xs = x * s;
    ys = y * s;
    zs = z * s;
    wx = w * xs;
    wy = w * ys;
    wz = w * zs;
    xx = x * xs;
    xy = x * ys;
    xz = x * zs;
    yy = y * ys;
    yz = y * zs;
    zz = z * zs;
    trace = (1.0 - (yy + zz)) + (1.0 - (xx + zz)) + (1.0 - (xx + yy));
    if (trace > 0.0) {
        s = sqrt(trace + 1.0);
        h = s * 0.5;
        s = 0.5 / s;
        q[0] = ((yz + wx) - (yz - wx)) * s;
        q[1] = ((xz + wy) - (xz - wy)) * s;
        q[2] = ((xy + wz) - (xy - wz)) * s;
        q[3] = h;
        return OK;
    }
    m00 = 1.0 - (yy + zz);
    m11 = 1.0 - (xx + zz);
    m22 = 1.0 - (xx + yy);
    m01 = xy - wz;
    m10 = xy + wz;
    m02 = xz + wy;
    m20 = xz - wy;
    m12 = yz - wx;
    m21 = yz + wx;
    i = m00 < m11 ? (m11 < m22 ? 2 : 1) : (m00 < m22 ? 2 : 0);
    if (i == 0)
        arg = m00 - m11 - m22 + 1.0;
    else if (i == 1)
        arg = m11 - m22 - m00 + 1.0;
    else
        arg = m22 - m00 - m11 + 1.0;
    if (arg < 0.0)
        return FALLBACK; /* math.sqrt raises */
    s = sqrt(arg);
    if (s == 0.0)
        return FALLBACK; /* 0.5 / 0.0 raises */
    h = s * 0.5;
    s = 0.5 / s;
    if (i == 0) {
        q[0] = h;
        q[1] = (m10 + m01) * s;
        q[2] = (m20 + m02) * s;
        q[3] = (m21 - m12) * s;
    }
    else if (i == 1) {
        q[0] = (m01 + m10) * s;
        q[1] = h;
        q[2] = (m21 + m12) * s;
        q[3] = (m02 - m20) * s;
    }
    else {
        q[0] = (m02 + m20) * s;
        q[1] = (m12 + m21) * s;
        q[2] = h;
        q[3] = (m10 - m01) * s;
    }
    return OK;
}

/* ---------------------------------------------------------------------------------------- */
/* the path                                                                                  */
/* ---------------------------------------------------------------------------------------- */

/* An edge is the tuple (stamps, parents, samples, slerp memo, expected parent, static cache):
 * the lists of a TimeCache (stamps None for a static edge, read from the StaticCache). */
static int
static_edge(PyObject *cache, long long expected, double *e)
{
    PyObject *o;
    long long parent;
    int rc;
    o = PyObject_GetAttr(cache, s_parent);
    if (o == NULL)
        return ERROR;
    rc = read_ll(o, &parent);
    Py_DECREF(o);
    if (rc != OK || parent != expected)
        return FALLBACK;
    o = PyObject_GetAttr(cache, s_sample);
    if (o == NULL)
        return ERROR;
    rc = read7(o, e);
    Py_DECREF(o);
    return rc;
}

/* the edge's parent_T_child at t (lerp + tf2 slerp between the bracketing samples) */
static int
edge_at(PyObject *edge, long long t, double *e)
{
    PyObject *stamps, *parents, *data, *ivs, *iv;
    long long expected, first, last, p, s0, s1;
    Py_ssize_t n, lo, hi, i;
    double a[7], b[7], r, u, theta, d, s0f, s1f;
    int flip, k;

    if (!PyTuple_Check(edge) || PyTuple_GET_SIZE(edge) != 6)
        return FALLBACK;
    stamps = PyTuple_GET_ITEM(edge, 0);
    if (read_ll(PyTuple_GET_ITEM(edge, 4), &expected) != OK)
        return FALLBACK;
    if (stamps == Py_None)
        return static_edge(PyTuple_GET_ITEM(edge, 5), expected, e);
    parents = PyTuple_GET_ITEM(edge, 1);
    data = PyTuple_GET_ITEM(edge, 2);
    ivs = PyTuple_GET_ITEM(edge, 3);
    if (!PyList_CheckExact(stamps) || !PyList_CheckExact(parents) || !PyList_CheckExact(data)
        || !PyList_CheckExact(ivs))
        return FALLBACK;
    n = PyList_GET_SIZE(stamps);
    if (n == 0 || PyList_GET_SIZE(parents) != n || PyList_GET_SIZE(data) != n
        || PyList_GET_SIZE(ivs) != n)
        return FALLBACK;
    if (list_ll(stamps, 0, &first) != OK || list_ll(stamps, n - 1, &last) != OK)
        return FALLBACK;
    if (first < t && t < last) {
        /* bisect_right(stamps, t) - 1 */
        lo = 0;
        hi = n;
        while (lo < hi) {
            Py_ssize_t mid = (lo + hi) / 2;
            long long v;
            if (list_ll(stamps, mid, &v) != OK)
                return FALLBACK;
            if (t < v)
                hi = mid;
            else
                lo = mid + 1;
        }
        i = lo - 1;
        if (list_ll(parents, i, &p) != OK || p != expected)
            return FALLBACK;
        if (list_ll(parents, i + 1, &p) != OK)
            return FALLBACK;
        if (p != expected) /* re-parented in between: no interpolation */
            return read7(PyList_GET_ITEM(data, i), e);
        if (list_ll(stamps, i, &s0) != OK || list_ll(stamps, i + 1, &s1) != OK)
            return FALLBACK;
        if (t - s0 >= EXACT_LIMIT || s1 - s0 >= EXACT_LIMIT)
            return FALLBACK;
        r = (double)(t - s0) / (double)(s1 - s0);
        u = 1.0 - r;
        if (read7(PyList_GET_ITEM(data, i), a) != OK
            || read7(PyList_GET_ITEM(data, i + 1), b) != OK)
            return FALLBACK;
        iv = PyList_GET_ITEM(ivs, i);
        if (iv == Py_None) {
            PyObject *memo;
            if (slerp_terms(a, b, &theta, &d, &flip) != OK)
                return FALLBACK;
            memo = Py_BuildValue("(ddO)", theta, d, flip ? Py_True : Py_False);
            if (memo == NULL)
                return ERROR;
            if (PyList_SetItem(ivs, i, memo) < 0) /* steals memo */
                return ERROR;
        }
        else {
            PyObject *ft, *fd, *ff;
            if (!PyTuple_Check(iv) || PyTuple_GET_SIZE(iv) != 3)
                return FALLBACK;
            ft = PyTuple_GET_ITEM(iv, 0);
            fd = PyTuple_GET_ITEM(iv, 1);
            ff = PyTuple_GET_ITEM(iv, 2);
            if (!PyFloat_CheckExact(ft) || !PyFloat_CheckExact(fd) || !PyBool_Check(ff))
                return FALLBACK;
            theta = PyFloat_AS_DOUBLE(ft);
            d = PyFloat_AS_DOUBLE(fd);
            flip = ff == Py_True;
        }
        e[4] = u * a[4] + r * b[4];
        e[5] = u * a[5] + r * b[5];
        e[6] = u * a[6] + r * b[6];
        if (theta == 0.0) {
            for (k = 0; k < 4; k++)
                e[k] = a[k];
        }
        else {
            s0f = sin(u * theta);
            s1f = flip ? -sin(r * theta) : sin(r * theta);
            for (k = 0; k < 4; k++)
                e[k] = (a[k] * s0f + b[k] * s1f) * d;
        }
        return OK;
    }
    if (t == last) {
        if (list_ll(parents, n - 1, &p) != OK || p != expected)
            return FALLBACK;
        return read7(PyList_GET_ITEM(data, n - 1), e);
    }
    return FALLBACK;
}

/* accumulated parent_T_child along a chain (a tuple of edges); identity for an empty chain */
static int
chain_at(PyObject *chain, long long t, double *acc)
{
    Py_ssize_t i, n;
    double e[7];
    int rc;
    if (!PyTuple_Check(chain))
        return FALLBACK;
    n = PyTuple_GET_SIZE(chain);
    acc[0] = acc[1] = acc[2] = acc[4] = acc[5] = acc[6] = 0.0;
    acc[3] = 1.0;
    for (i = 0; i < n; i++) {
        rc = edge_at(PyTuple_GET_ITEM(chain, i), t, e);
        if (rc != OK)
            return rc;
        if (i == 0)
            memcpy(acc, e, sizeof e);
        else
            accumulate(e, acc);
    }
    return OK;
}

/* whether TimeCache.get(t) certainly succeeds on this edge (static edges always do) */
static int
edge_evaluates(PyObject *edge, long long t)
{
    PyObject *stamps;
    long long first, last;
    Py_ssize_t n;
    if (!PyTuple_Check(edge) || PyTuple_GET_SIZE(edge) != 6)
        return FALLBACK;
    stamps = PyTuple_GET_ITEM(edge, 0);
    if (stamps == Py_None)
        return OK;
    if (!PyList_CheckExact(stamps))
        return FALLBACK;
    n = PyList_GET_SIZE(stamps);
    if (n == 0)
        return FALLBACK;
    if (list_ll(stamps, 0, &first) != OK || list_ll(stamps, n - 1, &last) != OK)
        return FALLBACK;
    return first < t && t <= last ? OK : FALLBACK;
}

static PyObject *
accel_evaluate(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    int mode, rc;
    long long t, sec, nsec;
    double a[7], b[7], out[7];
    PyObject *src, *tgt, *check;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "evaluate(mode, src, tgt, check, t)");
        return NULL;
    }
    mode = (int)PyLong_AsLong(args[0]);
    if (mode == -1 && PyErr_Occurred())
        return NULL;
    src = args[1];
    tgt = args[2];
    check = args[3];
    if (read_ll(args[4], &t) != OK)
        Py_RETURN_NONE;
    if (check != Py_None && edge_evaluates(check, t) != OK)
        Py_RETURN_NONE;
    if (mode == MODE_UP) {
        rc = chain_at(src, t, out);
    }
    else if (mode == MODE_DOWN) {
        rc = chain_at(src, t, a);
        if (rc == OK)
            rc = chain_at(tgt, t, b);
        if (rc == OK)
            inverse_rotate(b, NULL, out);
    }
    else if (mode == MODE_FULL) {
        rc = chain_at(src, t, a);
        if (rc == OK)
            rc = chain_at(tgt, t, b);
        if (rc == OK) {
            if (PyTuple_GET_SIZE(tgt) == 0)
                memcpy(out, a, sizeof a);
            else
                inverse_rotate(b, a, out);
        }
    }
    else {
        PyErr_SetString(PyExc_ValueError, "unknown path mode");
        return NULL;
    }
    if (rc == ERROR)
        return NULL;
    if (rc != OK || canonical(out) != OK)
        Py_RETURN_NONE;
    sec = t / NS_PER_S;
    nsec = t % NS_PER_S;
    if (nsec < 0) { /* Python's floor divmod */
        nsec += NS_PER_S;
        sec -= 1;
    }
    {
        PyObject *res = PyTuple_New(9), *o;
        int k;
        if (res == NULL)
            return NULL;
        o = PyLong_FromLongLong(sec);
        if (o == NULL)
            goto fail;
        PyTuple_SET_ITEM(res, 0, o);
        o = PyLong_FromLongLong(nsec);
        if (o == NULL)
            goto fail;
        PyTuple_SET_ITEM(res, 1, o);
        for (k = 0; k < 7; k++) {
            o = PyFloat_FromDouble(out[k]);
            if (o == NULL)
                goto fail;
            PyTuple_SET_ITEM(res, 2 + k, o);
        }
        return res;
    fail:
        Py_DECREF(res);
        return NULL;
    }
}

/* ---------------------------------------------------------------------------------------- */
/* set_transform: the sample of a message                                                    */
/* ---------------------------------------------------------------------------------------- */

static PyTypeObject *time_type;

/* slot members of the message classes, looked up once by configure() */
enum {
    M_TIME_SEC, M_TIME_NANOSEC, M_HEADER_STAMP, M_HEADER_FRAME_ID, M_VEC_X, M_VEC_Y, M_VEC_Z,
    M_QUAT_X, M_QUAT_Y, M_QUAT_Z, M_QUAT_W, M_TR_TRANSLATION, M_TR_ROTATION, M_TS_HEADER,
    M_TS_CHILD, M_TS_TRANSFORM, M_COUNT
};
enum { T_TIME, T_HEADER, T_VECTOR3, T_QUATERNION, T_TRANSFORM, T_STAMPED };
static PyMemberDef *members[M_COUNT];
static PyTypeObject *msg_types[6]; /* Time, Header, Vector3, Quaternion, Transform, TS */

/* obj.name: read straight from the slot when obj is exactly posekit's message class (the
 * same value getattr returns), else by getattr (rclpy, rosbags or other messages) */
static PyObject *
field(PyObject *obj, int type, int member, PyObject *name)
{
    if (Py_TYPE(obj) == msg_types[type])
        return PyMember_GetOne((const char *)obj, members[member]);
    return PyObject_GetAttr(obj, name);
}

/* exact float attributes of obj, in order; FALLBACK if one is not an exact float */
static int
read_floats(PyObject *obj, int type, int first_member, PyObject **names, int n, double *out)
{
    int k;
    for (k = 0; k < n; k++) {
        PyObject *f = field(obj, type, first_member + k, names[k]);
        if (f == NULL)
            return ERROR;
        if (!PyFloat_CheckExact(f)) {
            Py_DECREF(f);
            return FALLBACK;
        }
        out[k] = PyFloat_AS_DOUBLE(f);
        Py_DECREF(f);
    }
    return OK;
}

static int
valid_name(PyObject *name)
{
    return PyUnicode_CheckExact(name) && PyUnicode_GET_LENGTH(name) > 0
           && PyUnicode_READ_CHAR(name, 0) != '/';
}

static PyObject *
accel_sample_from_msg(PyObject *self, PyObject *msg)
{
    PyObject *tr = NULL, *vec = NULL, *rot = NULL, *header = NULL, *stamp = NULL;
    PyObject *parent = NULL, *child = NULL, *o, *result = NULL;
    PyObject *xyz[3] = {s_x, s_y, s_z};
    PyObject *xyzw[4] = {s_x, s_y, s_z, s_w};
    double v[3], q[4], dd;
    long long sec, nsec;
    int rc, overflow;

    if (time_type == NULL)
        Py_RETURN_NONE;
    tr = field(msg, T_STAMPED, M_TS_TRANSFORM, s_transform);
    if (tr == NULL)
        goto error;
    vec = field(tr, T_TRANSFORM, M_TR_TRANSLATION, s_translation);
    if (vec == NULL)
        goto error;
    rot = field(tr, T_TRANSFORM, M_TR_ROTATION, s_rotation);
    if (rot == NULL)
        goto error;
    rc = read_floats(vec, T_VECTOR3, M_VEC_X, xyz, 3, v);
    if (rc == OK)
        rc = read_floats(rot, T_QUATERNION, M_QUAT_X, xyzw, 4, q);
    if (rc == ERROR)
        goto error;
    if (rc != OK)
        goto fallback;
    dd = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (!(0.0 < dd && dd < HUGE_VAL))
        goto fallback;
    if (canonical(q) != OK)
        goto fallback;
    if (q[0] != q[0] || q[1] != q[1] || q[2] != q[2] || q[3] != q[3] || v[0] != v[0]
        || v[1] != v[1] || v[2] != v[2])
        goto fallback; /* rejected: the Python code logs why */
    header = field(msg, T_STAMPED, M_TS_HEADER, s_header);
    if (header == NULL)
        goto error;
    stamp = field(header, T_HEADER, M_HEADER_STAMP, s_stamp);
    if (stamp == NULL)
        goto error;
    if (Py_TYPE(stamp) != time_type)
        goto fallback;
    o = field(stamp, T_TIME, M_TIME_SEC, s_sec);
    if (o == NULL)
        goto error;
    sec = PyLong_CheckExact(o) ? PyLong_AsLongLongAndOverflow(o, &overflow) : 0;
    rc = PyLong_CheckExact(o) && !overflow && !PyErr_Occurred();
    Py_DECREF(o);
    PyErr_Clear();
    if (!rc || sec < -(1LL << 31) || sec >= (1LL << 31))
        goto fallback;
    o = field(stamp, T_TIME, M_TIME_NANOSEC, s_nanosec);
    if (o == NULL)
        goto error;
    nsec = PyLong_CheckExact(o) ? PyLong_AsLongLongAndOverflow(o, &overflow) : 0;
    rc = PyLong_CheckExact(o) && !overflow && !PyErr_Occurred();
    Py_DECREF(o);
    PyErr_Clear();
    if (!rc || nsec < 0 || nsec >= (1LL << 32))
        goto fallback;
    parent = field(header, T_HEADER, M_HEADER_FRAME_ID, s_frame_id);
    if (parent == NULL)
        goto error;
    child = field(msg, T_STAMPED, M_TS_CHILD, s_child_frame_id);
    if (child == NULL)
        goto error;
    if (!valid_name(parent) || !valid_name(child))
        goto fallback;
    rc = PyUnicode_Compare(parent, child);
    if (rc == -1 && PyErr_Occurred())
        goto error;
    if (rc == 0)
        goto fallback;
    {
        double sample[7] = {q[0], q[1], q[2], q[3], v[0], v[1], v[2]};
        PyObject *ns = PyLong_FromLongLong(sec * NS_PER_S + nsec), *values;
        if (ns == NULL)
            goto error;
        values = float_tuple(sample, 7);
        if (values == NULL) {
            Py_DECREF(ns);
            goto error;
        }
        result = PyTuple_New(4);
        if (result == NULL) {
            Py_DECREF(ns);
            Py_DECREF(values);
            goto error;
        }
        PyTuple_SET_ITEM(result, 0, ns);
        Py_INCREF(parent);
        PyTuple_SET_ITEM(result, 1, parent);
        Py_INCREF(child);
        PyTuple_SET_ITEM(result, 2, child);
        PyTuple_SET_ITEM(result, 3, values);
    }
    goto done;
fallback:
    result = Py_None;
    Py_INCREF(result);
    goto done;
error:
    result = NULL;
done:
    Py_XDECREF(tr);
    Py_XDECREF(vec);
    Py_XDECREF(rot);
    Py_XDECREF(header);
    Py_XDECREF(stamp);
    Py_XDECREF(parent);
    Py_XDECREF(child);
    return result;
}

/* ---------------------------------------------------------------------------------------- */
/* the result message                                                                        */
/* ---------------------------------------------------------------------------------------- */

static PyMemberDef *
member_of(PyTypeObject *cls, const char *name)
{
    PyObject *d = PyObject_GetAttrString((PyObject *)cls, name);
    PyMemberDef *m;
    if (d == NULL)
        return NULL;
    if (!Py_IS_TYPE(d, &PyMemberDescr_Type)) {
        Py_DECREF(d);
        PyErr_Format(PyExc_TypeError, "%s.%s is not a slot", cls->tp_name, name);
        return NULL;
    }
    m = ((PyMemberDescrObject *)d)->d_member;
    Py_DECREF(d); /* the class keeps the descriptor (and its PyMemberDef) alive */
    if (m->type != T_OBJECT_EX || (m->flags & READONLY)) {
        PyErr_Format(PyExc_TypeError, "%s.%s is not a writable object slot", cls->tp_name,
                     name);
        return NULL;
    }
    return m;
}

static PyObject *
accel_configure(PyObject *self, PyObject *args)
{
    static const struct {
        int type;
        const char *name;
    } fields[M_COUNT] = {
        {0, "sec"}, {0, "nanosec"}, {1, "stamp"}, {1, "frame_id"}, {2, "x"}, {2, "y"},
        {2, "z"}, {3, "x"}, {3, "y"}, {3, "z"}, {3, "w"}, {4, "translation"},
        {4, "rotation"}, {5, "header"}, {5, "child_frame_id"}, {5, "transform"},
    };
    PyTypeObject *types[6];
    PyMemberDef *found[M_COUNT];
    int k;
    if (!PyArg_ParseTuple(args, "O!O!O!O!O!O!", &PyType_Type, &types[0], &PyType_Type,
                          &types[1], &PyType_Type, &types[2], &PyType_Type, &types[3],
                          &PyType_Type, &types[4], &PyType_Type, &types[5]))
        return NULL;
    for (k = 0; k < M_COUNT; k++) {
        found[k] = member_of(types[fields[k].type], fields[k].name);
        if (found[k] == NULL)
            return NULL;
    }
    for (k = 0; k < 6; k++) {
        Py_INCREF(types[k]);
        Py_XSETREF(msg_types[k], types[k]);
    }
    memcpy(members, found, sizeof found);
    time_type = msg_types[0];
    Py_RETURN_NONE;
}

/* a new instance of a slots class, as object.__new__(cls) makes it (every slot unset) */
static PyObject *
blank(PyTypeObject *cls)
{
    return cls->tp_alloc(cls, 0);
}

static int
set_member(PyObject *obj, int which, PyObject *value)
{
    int rc;
    if (value == NULL)
        return -1;
    rc = PyMember_SetOne((char *)obj, members[which], value);
    Py_DECREF(value);
    return rc;
}

static PyObject *
accel_stamped(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    PyObject *r, *stamp = NULL, *header = NULL, *vec = NULL, *rot = NULL, *tr = NULL, *msg;
    Py_ssize_t k;
    if (nargs != 3 || !PyTuple_Check(args[2]) || PyTuple_GET_SIZE(args[2]) != 9) {
        PyErr_SetString(PyExc_TypeError, "stamped(target, source, 9-tuple)");
        return NULL;
    }
    if (msg_types[0] == NULL) {
        PyErr_SetString(PyExc_RuntimeError, "configure() was not called");
        return NULL;
    }
    r = args[2];
    for (k = 0; k < 9; k++)
        Py_INCREF(PyTuple_GET_ITEM(r, k));
    stamp = blank(msg_types[0]);
    header = blank(msg_types[1]);
    vec = blank(msg_types[2]);
    rot = blank(msg_types[3]);
    tr = blank(msg_types[4]);
    msg = blank(msg_types[5]);
    if (stamp == NULL || header == NULL || vec == NULL || rot == NULL || tr == NULL
        || msg == NULL)
        goto error;
    /* set_member steals the value's reference (taken above or just created) */
    if (set_member(stamp, M_TIME_SEC, PyTuple_GET_ITEM(r, 0)) < 0
        || set_member(stamp, M_TIME_NANOSEC, PyTuple_GET_ITEM(r, 1)) < 0
        || set_member(rot, M_QUAT_X, PyTuple_GET_ITEM(r, 2)) < 0
        || set_member(rot, M_QUAT_Y, PyTuple_GET_ITEM(r, 3)) < 0
        || set_member(rot, M_QUAT_Z, PyTuple_GET_ITEM(r, 4)) < 0
        || set_member(rot, M_QUAT_W, PyTuple_GET_ITEM(r, 5)) < 0
        || set_member(vec, M_VEC_X, PyTuple_GET_ITEM(r, 6)) < 0
        || set_member(vec, M_VEC_Y, PyTuple_GET_ITEM(r, 7)) < 0
        || set_member(vec, M_VEC_Z, PyTuple_GET_ITEM(r, 8)) < 0) {
        r = NULL; /* the remaining references were consumed or are released below */
        goto error;
    }
    Py_INCREF(args[0]);
    Py_INCREF(args[1]);
    if (set_member(header, M_HEADER_STAMP, stamp) < 0
        || set_member(header, M_HEADER_FRAME_ID, args[0]) < 0
        || set_member(tr, M_TR_TRANSLATION, vec) < 0 || set_member(tr, M_TR_ROTATION, rot) < 0
        || set_member(msg, M_TS_HEADER, header) < 0
        || set_member(msg, M_TS_CHILD, args[1]) < 0
        || set_member(msg, M_TS_TRANSFORM, tr) < 0) {
        Py_DECREF(msg);
        return NULL; /* cannot happen for writable object slots */
    }
    return msg;
error:
    Py_XDECREF(stamp);
    Py_XDECREF(header);
    Py_XDECREF(vec);
    Py_XDECREF(rot);
    Py_XDECREF(tr);
    Py_XDECREF(msg);
    (void)r;
    return NULL;
}

static PyMethodDef accel_methods[] = {
    {"evaluate", (PyCFunction)(void (*)(void))accel_evaluate, METH_FASTCALL,
     "evaluate(mode, src, tgt, check, t): a cached path's finished result, or None."},
    {"sample_from_msg", accel_sample_from_msg, METH_O,
     "sample_from_msg(msg): (stamp_ns, parent, child, sample) of a valid message, or None."},
    {"stamped", (PyCFunction)(void (*)(void))accel_stamped, METH_FASTCALL,
     "stamped(target, source, result): the TransformStamped of a finished result."},
    {"configure", accel_configure, METH_VARARGS,
     "configure(Time, Header, Vector3, Quaternion, Transform, TransformStamped)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef accel_module = {
    PyModuleDef_HEAD_INIT, "posekit.tf2._accel",
    "Compiled kernels of the tf2 lookup engine (see posekit.tf2.path).", -1, accel_methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC
PyInit__accel(void)
{
#define INTERN(var, text)                                                                  \
    if ((var = PyUnicode_InternFromString(text)) == NULL)                                  \
        return NULL;
    INTERN(s_parent, "parent")
    INTERN(s_sample, "sample")
    INTERN(s_transform, "transform")
    INTERN(s_translation, "translation")
    INTERN(s_rotation, "rotation")
    INTERN(s_header, "header")
    INTERN(s_stamp, "stamp")
    INTERN(s_frame_id, "frame_id")
    INTERN(s_child_frame_id, "child_frame_id")
    INTERN(s_sec, "sec")
    INTERN(s_nanosec, "nanosec")
    INTERN(s_x, "x")
    INTERN(s_y, "y")
    INTERN(s_z, "z")
    INTERN(s_w, "w")
#undef INTERN
    return PyModule_Create(&accel_module);
}
