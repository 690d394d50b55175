/* The servo loop stepped tick by tick, compiled: the same arithmetic, in the same order,
 * as ServoLoop._scalar_python in servo.py (the reference), and the commanded position as
 * profiles.Motion.offset and path.ContourMotion.offset compute it.
 *
 * Built with -ffp-contract=off and without fast-math, every operation rounds as CPython's
 * float arithmetic does, and sin, cos and pow are the same C library's: the two loops agree
 * to the last bit (tests/test_servo_kernel.py checks it).
 *
 * step(state, params, program, tick, count) -> int
 *   state:   array('d') of STATE_SIZE, read and written (layout: servo_kernel.py)
 *   params:  array('d') of PARAM_SIZE (the filter, the plant, the encoder offset)
 *   program: array('d'), the commanded position (a motion's description)
 *   returns the ticks stepped (count), or -(ticks + 1) when the following error tripped
 *   at tick + ticks (that tick not stepped).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

enum { P, W, S, Q, DAC, RPREV, RPREV2, HAS_PREV, HAS_PREV2, CLOSED, TRIPPED, STUCK,
       STATE_SIZE };
enum { A11, A12, A21, A22, B1, B2, FRICTION, KP, KD, KI, KV, KA, KF, KO, CAP, EO,
       PARAM_SIZE };
/* program header */
enum { KIND, BASE, MSTART, MEND, HAS_MEND, PERIOD, FINAL, END_TIME, HAS_END_TIME, COUNT1,
       COUNT2, AXIS_K, ORIGIN, S_END, HEADER };
enum { KIND_REST = 0, KIND_PROFILE = 1, KIND_CONTOUR = 2 };
/* a profile phase */
enum { PH_T0, PH_DURATION, PH_S0, PH_V1, PH_V2, PH_DIRECTION, PH_SHAPE, PH_MIRRORED,
       PHASE_SIZE };
enum { SHAPE_LINEAR, SHAPE_PARABOLIC, SHAPE_SCURVE, SHAPE_COSINE };
/* a path piece and a path segment */
enum { PC_T0, PC_DURATION, PC_S0, PC_V0, PC_A, PIECE_SIZE };
enum { SG_S0, SG_LENGTH, SG_ARC, SG_START, SG_UNIT, SG_END, SG_CX, SG_CY, SG_RADIUS,
       SG_THETA0, SG_TURN, SEGMENT_SIZE };

#define FOLLOWING_ERROR_LIMIT 32768.0
#define DAC_LIMIT 32767.0
#define SETTLED_ERROR 1e-3

/* Python's min(a, b) and max(a, b): the first argument unless the second is strictly
 * smaller (larger); this keeps the sign of zero as Python does. */
static inline double py_min(double a, double b) { return b < a ? b : a; }
static inline double py_max(double a, double b) { return b > a ? b : a; }

static double shape_integral(int shape, double u)
{
    switch (shape) {
    case SHAPE_LINEAR:
        return u * u / 2.0;
    case SHAPE_PARABOLIC:
        return u * u - pow(u, 3.0) / 3.0;
    case SHAPE_SCURVE:
        if (u < 0.5)
            return 2.0 * pow(u, 3.0) / 3.0;
        else {
            double w = 1.0 - u;
            return 1.0 / 12.0 + (u - 0.5) - 2.0 * (0.125 - pow(w, 3.0)) / 3.0;
        }
    default:
        return u / 2.0 - sin(M_PI * u) / (2.0 * M_PI);
    }
}

static double phase_distance(const double *ph, double tau)
{
    double v1 = ph[PH_V1], v2 = ph[PH_V2];
    if (v1 == v2)
        return v1 * tau;
    double T = ph[PH_DURATION];
    double u = py_min(py_max(tau / T, 0.0), 1.0);
    int shape = (int)ph[PH_SHAPE];
    if (ph[PH_MIRRORED] != 0.0) {
        double full = shape_integral(shape, 1.0);
        return v2 * tau + (v1 - v2) * T * (full - shape_integral(shape, 1.0 - u));
    }
    return v1 * tau + (v2 - v1) * T * shape_integral(shape, u);
}

/* The largest i with times[i * stride] <= t (0 if none), from a cursor: what
 * Motion.phase_at and bisect_right(...) - 1 clamped at 0 both give. */
static Py_ssize_t locate(const double *rows, Py_ssize_t n, Py_ssize_t stride, double t,
                         Py_ssize_t *cursor)
{
    Py_ssize_t i = *cursor;
    if (i >= n || rows[i * stride] > t)
        i = 0;
    while (i + 1 < n && rows[(i + 1) * stride] <= t)
        i++;
    *cursor = i;
    return i;
}

typedef struct {
    Py_ssize_t phase, piece, segment;
} Cursors;

static double profile_offset(const double *prog, double t, Cursors *c)
{
    if (prog[HAS_END_TIME] != 0.0 && t >= prog[END_TIME])
        return prog[FINAL];
    Py_ssize_t n = (Py_ssize_t)prog[COUNT1];
    if (n == 0)
        return prog[FINAL];
    const double *phases = prog + HEADER;
    const double *ph = phases + locate(phases + PH_T0, n, PHASE_SIZE, t, &c->phase) * PHASE_SIZE;
    return ph[PH_S0] + ph[PH_DIRECTION] * phase_distance(ph, t - ph[PH_T0]);
}

static double contour_offset(const double *prog, double t, Cursors *c)
{
    if (prog[HAS_END_TIME] != 0.0 && t >= prog[END_TIME])
        return prog[FINAL];
    Py_ssize_t n_pieces = (Py_ssize_t)prog[COUNT1], n_segments = (Py_ssize_t)prog[COUNT2];
    const double *pieces = prog + HEADER;
    const double *segments = pieces + n_pieces * PIECE_SIZE;
    double s;
    if (n_pieces == 0) {
        s = prog[S_END];
    } else {
        Py_ssize_t i = locate(pieces + PC_T0, n_pieces, PIECE_SIZE, t, &c->piece);
        const double *pc = pieces + i * PIECE_SIZE;
        double tau = py_min(t - pc[PC_T0], pc[PC_DURATION]);
        s = pc[PC_S0] + pc[PC_V0] * tau + 0.5 * pc[PC_A] * tau * tau;
        if (i + 1 < n_pieces)
            s = py_min(s, pieces[(i + 1) * PIECE_SIZE + PC_S0]);
    }
    /* PathPlan.segment_at, then Segment.coordinate */
    Py_ssize_t i = locate(segments + SG_S0, n_segments, SEGMENT_SIZE, s, &c->segment);
    while (i > 0 && segments[i * SEGMENT_SIZE + SG_LENGTH] == 0.0
           && segments[i * SEGMENT_SIZE + SG_S0] >= s)
        i--;
    const double *sg = segments + i * SEGMENT_SIZE;
    double sigma = s - sg[SG_S0], point;
    int k = (int)prog[AXIS_K];
    if (sigma >= sg[SG_LENGTH])
        point = sg[SG_END];
    else if (sg[SG_ARC] == 0.0)
        point = sg[SG_START] + sg[SG_UNIT] * sigma;
    else if (k > 1 || sg[SG_RADIUS] == 0.0)
        point = sg[SG_START];
    else {
        double theta = sg[SG_THETA0] + copysign(sigma / sg[SG_RADIUS], sg[SG_TURN]);
        point = k == 0 ? sg[SG_CX] + sg[SG_RADIUS] * cos(theta)
                       : sg[SG_CY] + sg[SG_RADIUS] * sin(theta);
    }
    return point - prog[ORIGIN];
}

/* ServoLoop._commanded: the commanded position (counter frame) at a tick */
static double commanded(const double *prog, long long tick, Cursors *c)
{
    int kind = (int)prog[KIND];
    if (kind == KIND_REST)
        return prog[BASE];
    if (prog[HAS_MEND] != 0.0 && (double)tick >= prog[MEND])
        return prog[BASE] + prog[FINAL];
    double t = (double)(tick - (long long)prog[MSTART]) * prog[PERIOD];
    double offset = kind == KIND_PROFILE ? profile_offset(prog, t, c) : contour_offset(prog, t, c);
    return prog[BASE] + offset;
}

static long long run(double *x, const double *k, const double *prog, long long tick0,
                     long long count)
{
    const double a11 = k[A11], a12 = k[A12], a21 = k[A21], a22 = k[A22], b1 = k[B1],
                 b2 = k[B2], friction = k[FRICTION], kp = k[KP], kd = k[KD], ki = k[KI],
                 kv = k[KV], ka = k[KA], kf = k[KF], ko = k[KO], cap = k[CAP], eo = k[EO];
    double p = x[P], w = x[W], s = x[S], q = x[Q], dac = x[DAC], r_prev = x[RPREV],
           r_prev2 = x[RPREV2];
    int has_prev = x[HAS_PREV] != 0.0, has_prev2 = x[HAS_PREV2] != 0.0;
    const int closed = x[CLOSED] != 0.0, tripped = x[TRIPPED] != 0.0;
    int stuck = x[STUCK] != 0.0;
    Cursors cursors = {0, 0, 0};
    long long done = 0, result;
    for (; done < count; done++) {
        long long tick = tick0 + done;
        double r_abs = commanded(prog, tick, &cursors);
        double r = r_abs - eo;
        double v = has_prev ? r_abs - r_prev : 0.0;
        double v_prev = has_prev && has_prev2 ? r_prev - r_prev2 : 0.0;
        double a = v - v_prev;
        double e = r - p;
        double u;
        if (tripped) {
            u = 0.0;
        } else if (!closed) {
            u = ko;
        } else {
            if (fabs(e) > FOLLOWING_ERROR_LIMIT) {
                result = -(done + 1);
                goto out;
            }
            int held = stuck && fabs(e) < SETTLED_ERROR;
            double s_new = ki > 0 && !held ? s + e : ki > 0 ? s : 0.0;
            s_new = py_max(-cap, py_min(cap, s_new));
            double sign_v = v > 1e-12 ? 1.0 : v < -1e-12 ? -1.0 : 0.0;
            u = kp * e + kd * (e - q) + ki * s_new + kv * v + ka * a + kf * sign_v + ko;
            s = s_new;
            q = e;
        }
        u = py_max(-DAC_LIMIT, py_min(DAC_LIMIT, u));
        dac = u;
        r_prev2 = r_prev;
        has_prev2 = has_prev;
        r_prev = r_abs;
        has_prev = 1;
        if (stuck) {
            if (fabs(u) <= friction)
                continue;
            stuck = 0;
        }
        double drive, w0 = w;
        if (friction != 0.0) {
            double direction = w0 != 0.0 ? (w0 > 0 ? 1.0 : -1.0) : (u > 0 ? 1.0 : -1.0);
            drive = u - friction * direction;
            if (w0 == 0.0 && fabs(u) <= friction) {
                stuck = 1;
                continue;
            }
        } else {
            drive = u;
        }
        double p_new = a11 * p + a12 * w0 + b1 * drive;
        double w_new = a21 * p + a22 * w0 + b2 * drive;
        if (friction != 0.0 && w0 != 0.0 && (w_new > 0) != (w0 > 0) && fabs(u) <= friction) {
            w_new = 0.0;
            stuck = 1;
        }
        p = p_new;
        w = w_new;
    }
    result = done;
out:
    x[P] = p;
    x[W] = w;
    x[S] = s;
    x[Q] = q;
    x[DAC] = dac;
    x[RPREV] = r_prev;
    x[RPREV2] = r_prev2;
    x[HAS_PREV] = has_prev;
    x[HAS_PREV2] = has_prev2;
    x[STUCK] = stuck;
    return result;
}

static int get_doubles(PyObject *obj, Py_buffer *view, int writable, Py_ssize_t least,
                       const char *what)
{
    if (PyObject_GetBuffer(obj, view, (writable ? PyBUF_WRITABLE : PyBUF_SIMPLE)
                           | PyBUF_FORMAT) < 0)
        return -1;
    if (view->itemsize != sizeof(double) || view->format == NULL
        || strcmp(view->format, "d") != 0 || view->len / (Py_ssize_t)sizeof(double) < least) {
        PyErr_Format(PyExc_ValueError, "%s: an array('d') of at least %zd doubles", what,
                     least);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

static Py_ssize_t program_size(const double *prog, Py_ssize_t available)
{
    if (available < HEADER)
        return -1;
    int kind = (int)prog[KIND];
    Py_ssize_t n1 = (Py_ssize_t)prog[COUNT1], n2 = (Py_ssize_t)prog[COUNT2];
    if (n1 < 0 || n2 < 0)
        return -1;
    switch (kind) {
    case KIND_REST:
        return HEADER;
    case KIND_PROFILE:
        return HEADER + n1 * PHASE_SIZE;
    case KIND_CONTOUR:
        return n2 < 1 ? -1 : HEADER + n1 * PIECE_SIZE + n2 * SEGMENT_SIZE;
    default:
        return -1;
    }
}

static PyObject *step(PyObject *module, PyObject *const *args, Py_ssize_t nargs)
{
    (void)module;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "step(state, params, program, tick, count)");
        return NULL;
    }
    long long tick = PyLong_AsLongLong(args[3]);
    if (tick == -1 && PyErr_Occurred())
        return NULL;
    long long count = PyLong_AsLongLong(args[4]);
    if (count == -1 && PyErr_Occurred())
        return NULL;
    Py_buffer state, params, program;
    if (get_doubles(args[0], &state, 1, STATE_SIZE, "state") < 0)
        return NULL;
    if (get_doubles(args[1], &params, 0, PARAM_SIZE, "params") < 0) {
        PyBuffer_Release(&state);
        return NULL;
    }
    if (get_doubles(args[2], &program, 0, HEADER, "program") < 0) {
        PyBuffer_Release(&state);
        PyBuffer_Release(&params);
        return NULL;
    }
    const double *prog = program.buf;
    Py_ssize_t size = program_size(prog, program.len / (Py_ssize_t)sizeof(double));
    long long result = 0;
    int ok = size >= 0 && size <= program.len / (Py_ssize_t)sizeof(double);
    if (ok && count > 0)
        result = run(state.buf, params.buf, prog, tick, count);
    PyBuffer_Release(&state);
    PyBuffer_Release(&params);
    PyBuffer_Release(&program);
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "program: not a motion's description");
        return NULL;
    }
    return PyLong_FromLongLong(result);
}

/* step_axes(axes, limit) -> the axes it could not step
 *
 * A pacing pass over a board's servo axes in one call: for each axis whose loop is inside
 * a stretch the kernel steps (loop._fast = (until, key, plant, friction, gains, (params,
 * program), checks)), with no trip pending, no recorder, limit <= until and every check
 * (object, attribute name, value the stretch was planned with) still holding, it steps
 * the loop to `limit` (loop.tick, and loop.trip_tick on a trip). The others are returned
 * for ServoLoop.advance, which remakes its decisions in Python. */
static int holds(PyObject *checks)
{
    if (!PyTuple_Check(checks))
        return 0;
    Py_ssize_t n = PyTuple_GET_SIZE(checks);
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *check = PyTuple_GET_ITEM(checks, i);
        if (!PyTuple_Check(check) || PyTuple_GET_SIZE(check) != 3)
            return 0;
        PyObject *now = PyObject_GetAttr(PyTuple_GET_ITEM(check, 0), PyTuple_GET_ITEM(check, 1));
        if (now == NULL)
            return -1;
        int same = PyObject_RichCompareBool(now, PyTuple_GET_ITEM(check, 2), Py_EQ);
        Py_DECREF(now);
        if (same != 1)
            return same;
    }
    return 1;
}

static PyObject *s_servo, *s_fast, *s_trip_tick, *s_recorder, *s_tick, *s_x;

/* 1: stepped; 0: not for the kernel (left to Python); -1: an error */
static int step_one(PyObject *axis, long long limit)
{
    int result = 0;
    PyObject *loop = NULL, *fast = NULL, *attr = NULL;
    Py_buffer state = {0}, params = {0}, program = {0};
    int have_state = 0, have_params = 0, have_program = 0;
    loop = PyObject_GetAttr(axis, s_servo);
    if (loop == NULL)
        return -1;
    fast = PyObject_GetAttr(loop, s_fast);
    if (fast == NULL) {
        result = -1;
        goto done;
    }
    if (!PyTuple_Check(fast) || PyTuple_GET_SIZE(fast) != 7)
        goto done;
    long long until = PyLong_AsLongLong(PyTuple_GET_ITEM(fast, 0));
    if (until == -1 && PyErr_Occurred()) {
        PyErr_Clear();
        goto done;
    }
    if (limit > until)
        goto done;
    attr = PyObject_GetAttr(loop, s_trip_tick);
    if (attr == NULL || attr != Py_None) {
        result = attr == NULL ? -1 : 0;
        goto done;
    }
    Py_DECREF(attr);
    attr = PyObject_GetAttr(loop, s_recorder);
    if (attr == NULL || attr != Py_None) {
        result = attr == NULL ? -1 : 0;
        goto done;
    }
    Py_CLEAR(attr);
    int ok = holds(PyTuple_GET_ITEM(fast, 6));
    if (ok != 1) {
        result = ok;
        goto done;
    }
    PyObject *kernel = PyTuple_GET_ITEM(fast, 5);
    if (!PyTuple_Check(kernel) || PyTuple_GET_SIZE(kernel) != 2)
        goto done;
    attr = PyObject_GetAttr(loop, s_tick);
    if (attr == NULL) {
        result = -1;
        goto done;
    }
    long long tick = PyLong_AsLongLong(attr);
    Py_CLEAR(attr);
    if (tick == -1 && PyErr_Occurred()) {
        result = -1;
        goto done;
    }
    if (tick >= limit) {
        result = 1;
        goto done;
    }
    attr = PyObject_GetAttr(loop, s_x);
    if (attr == NULL) {
        result = -1;
        goto done;
    }
    if (get_doubles(attr, &state, 1, STATE_SIZE, "state") < 0) {
        result = -1;
        goto done;
    }
    have_state = 1;
    if (get_doubles(PyTuple_GET_ITEM(kernel, 0), &params, 0, PARAM_SIZE, "params") < 0) {
        result = -1;
        goto done;
    }
    have_params = 1;
    if (get_doubles(PyTuple_GET_ITEM(kernel, 1), &program, 0, HEADER, "program") < 0) {
        result = -1;
        goto done;
    }
    have_program = 1;
    Py_ssize_t size = program_size(program.buf, program.len / (Py_ssize_t)sizeof(double));
    if (size < 0 || size > program.len / (Py_ssize_t)sizeof(double)) {
        PyErr_SetString(PyExc_ValueError, "program: not a motion's description");
        result = -1;
        goto done;
    }
    long long stepped = run(state.buf, params.buf, program.buf, tick, limit - tick);
    long long reached = tick + (stepped < 0 ? -stepped - 1 : stepped);
    PyObject *value = PyLong_FromLongLong(reached);
    if (value == NULL || PyObject_SetAttr(loop, s_tick, value) < 0
        || (stepped < 0 && PyObject_SetAttr(loop, s_trip_tick, value) < 0)) {
        Py_XDECREF(value);
        result = -1;
        goto done;
    }
    Py_DECREF(value);
    result = 1;
done:
    if (have_state)
        PyBuffer_Release(&state);
    if (have_params)
        PyBuffer_Release(&params);
    if (have_program)
        PyBuffer_Release(&program);
    Py_XDECREF(attr);
    Py_XDECREF(fast);
    Py_DECREF(loop);
    return result;
}

static PyObject *step_axes(PyObject *module, PyObject *const *args, Py_ssize_t nargs)
{
    (void)module;
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "step_axes(axes, limit)");
        return NULL;
    }
    long long limit = PyLong_AsLongLong(args[1]);
    if (limit == -1 && PyErr_Occurred())
        return NULL;
    PyObject *axes = PySequence_Fast(args[0], "step_axes: axes is a sequence");
    if (axes == NULL)
        return NULL;
    PyObject *rest = PyList_New(0);
    if (rest == NULL) {
        Py_DECREF(axes);
        return NULL;
    }
    Py_ssize_t n = PySequence_Fast_GET_SIZE(axes);
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *axis = PySequence_Fast_GET_ITEM(axes, i);
        int stepped = step_one(axis, limit);
        if (stepped < 0 || (stepped == 0 && PyList_Append(rest, axis) < 0)) {
            Py_DECREF(rest);
            Py_DECREF(axes);
            return NULL;
        }
    }
    Py_DECREF(axes);
    return rest;
}

static PyMethodDef methods[] = {
    {"step_axes", (PyCFunction)(void (*)(void))step_axes, METH_FASTCALL,
     "step_axes(axes, limit) -> the axes it could not step (see the source)"},
    {"step", (PyCFunction)(void (*)(void))step, METH_FASTCALL,
     "step(state, params, program, tick, count) -> ticks stepped, or -(ticks + 1) on a "
     "following-error trip"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_servo_kernel",
    "The servo loop stepped tick by tick, compiled (see servo_kernel.py).", -1, methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__servo_kernel(void)
{
    s_servo = PyUnicode_InternFromString("servo");
    s_fast = PyUnicode_InternFromString("_fast");
    s_trip_tick = PyUnicode_InternFromString("trip_tick");
    s_recorder = PyUnicode_InternFromString("recorder");
    s_tick = PyUnicode_InternFromString("tick");
    s_x = PyUnicode_InternFromString("x");
    if (!s_servo || !s_fast || !s_trip_tick || !s_recorder || !s_tick || !s_x)
        return NULL;
    PyObject *m = PyModule_Create(&module);
    if (m == NULL)
        return NULL;
    if (PyModule_AddIntConstant(m, "STATE_SIZE", STATE_SIZE) < 0
        || PyModule_AddIntConstant(m, "PARAM_SIZE", PARAM_SIZE) < 0
        || PyModule_AddIntConstant(m, "HEADER", HEADER) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
