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
#include <limits.h>
#include <math.h>

enum { P, W, S, Q, DAC, RPREV, RPREV2, HAS_PREV, HAS_PREV2, CLOSED, TRIPPED, STUCK,
       STATE_SIZE };
enum { A11, A12, A21, A22, B1, B2, FRICTION, KP, KD, KI, KV, KA, KF, KO, CAP, EO, FDIR,
       PARAM_SIZE };
/* program header */
enum { KIND, BASE, MSTART, MEND, HAS_MEND, PERIOD, FINAL, END_TIME, HAS_END_TIME, COUNT1,
       COUNT2, AXIS_K, ORIGIN, S_END, HEADER };
enum { KIND_REST = 0, KIND_PROFILE = 1, KIND_CONTOUR = 2, KIND_CONTOUR_JERK = 3 };
/* a profile phase */
enum { PH_T0, PH_DURATION, PH_S0, PH_V1, PH_V2, PH_DIRECTION, PH_SHAPE, PH_MIRRORED,
       PHASE_SIZE };
enum { SHAPE_LINEAR, SHAPE_PARABOLIC, SHAPE_SCURVE, SHAPE_COSINE };
/* a path piece and a path segment */
enum { PC_T0, PC_DURATION, PC_S0, PC_V0, PC_A, PIECE_SIZE };
/* a contour with S-ramps (path_scurve.py) has pieces of constant jerk: one more value */
enum { PC_J = PIECE_SIZE, JERK_PIECE_SIZE };
enum { SG_S0, SG_LENGTH, SG_ARC, SG_START, SG_UNIT, SG_END, SG_CX, SG_CY, SG_RADIUS,
       SG_THETA0, SG_TURN, SEGMENT_SIZE };

/* the step of one tick inlined where it is used (the loop's state then stays in registers) */
#if defined(__GNUC__) || defined(__clang__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif

#define FOLLOWING_ERROR_LIMIT 32768.0
#define DAC_LIMIT 32767.0
#define SETTLED_ERROR 1e-3
#define JUMP_MIN 64       /* ticks: a shorter stretch is stepped */
#define JUMP_BACKOFF 64   /* ticks stepped before trying again where a bound failed */
#define JUMP_BACKOFF_MAX 8192
#define NEVER LLONG_MAX

/* Python's min(a, b) and max(a, b): the first argument unless the second is strictly
 * smaller (larger); this keeps the sign of zero as Python does. */
static inline double py_min(double a, double b) { return b < a ? b : a; }
static inline double py_max(double a, double b) { return b > a ? b : a; }

static ALWAYS_INLINE double shape_integral(int shape, double u)
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

static ALWAYS_INLINE double phase_distance(const double *ph, double tau)
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

/* The phase a profile is in, held from one tick to the next: phase `ph` holds for t in
 * [lo, hi) (lo -inf for the first phase, hi +inf for the last), which is where locate()
 * would find it. */
typedef struct {
    const double *ph;
    double lo, hi;
} PhaseCache;

static ALWAYS_INLINE double profile_offset(const double *prog, double t, Cursors *c,
                                           PhaseCache *pc)
{
    if (prog[HAS_END_TIME] != 0.0 && t >= prog[END_TIME])
        return prog[FINAL];
    Py_ssize_t n = (Py_ssize_t)prog[COUNT1];
    if (n == 0)
        return prog[FINAL];
    const double *ph = pc->ph;
    if (ph == NULL || !(t >= pc->lo && t < pc->hi)) {
        const double *phases = prog + HEADER;
        Py_ssize_t i = locate(phases + PH_T0, n, PHASE_SIZE, t, &c->phase);
        ph = phases + i * PHASE_SIZE;
        pc->ph = ph;
        pc->lo = i == 0 ? -HUGE_VAL : ph[PH_T0];
        pc->hi = i + 1 < n ? phases[(i + 1) * PHASE_SIZE + PH_T0] : HUGE_VAL;
    }
    return ph[PH_S0] + ph[PH_DIRECTION] * phase_distance(ph, t - ph[PH_T0]);
}

static ALWAYS_INLINE double contour_offset(const double *prog, double t, Cursors *c,
                                           int jerked)
{
    Py_ssize_t size = jerked ? JERK_PIECE_SIZE : PIECE_SIZE;
    if (prog[HAS_END_TIME] != 0.0 && t >= prog[END_TIME])
        return prog[FINAL];
    Py_ssize_t n_pieces = (Py_ssize_t)prog[COUNT1], n_segments = (Py_ssize_t)prog[COUNT2];
    const double *pieces = prog + HEADER;
    const double *segments = pieces + n_pieces * size;
    double s;
    if (n_pieces == 0) {
        s = prog[S_END];
    } else {
        Py_ssize_t i = locate(pieces + PC_T0, n_pieces, size, t, &c->piece);
        const double *pc = pieces + i * size;
        double tau = py_min(t - pc[PC_T0], pc[PC_DURATION]);
        if (jerked && pc[PC_J] != 0.0)  /* Piece.s with its jerk */
            s = pc[PC_S0] + tau * (pc[PC_V0] + tau * (0.5 * pc[PC_A] + tau * pc[PC_J] / 6.0));
        else
            s = pc[PC_S0] + pc[PC_V0] * tau + 0.5 * pc[PC_A] * tau * tau;
        if (i + 1 < n_pieces)
            s = py_min(s, pieces[(i + 1) * size + PC_S0]);
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

/* The program's header, decoded once per call rather than at every tick. */
typedef struct {
    int kind, has_mend;
    long long mstart;
    double base, mend, period, end_position;
    PhaseCache phase;
} Header;

static void decode(Header *h, const double *prog)
{
    h->kind = (int)prog[KIND];
    h->has_mend = prog[HAS_MEND] != 0.0;
    h->mstart = h->kind == KIND_REST ? 0 : (long long)prog[MSTART];
    h->base = prog[BASE];
    h->mend = prog[MEND];
    h->period = prog[PERIOD];
    h->end_position = prog[BASE] + prog[FINAL];
    h->phase.ph = NULL;
    h->phase.lo = h->phase.hi = 0.0;
}

/* ServoLoop._commanded: the commanded position (counter frame) at a tick */
static ALWAYS_INLINE double commanded(const double *prog, Header *h, long long tick,
                                      Cursors *c)
{
    int kind = h->kind;
    if (kind == KIND_REST)
        return h->base;
    if (h->has_mend && (double)tick >= h->mend)
        return h->end_position;
    double t = (double)(tick - h->mstart) * h->period;
    double offset = kind == KIND_PROFILE ? profile_offset(prog, t, c, &h->phase)
                                         : contour_offset(prog, t, c,
                                                          kind == KIND_CONTOUR_JERK);
    return h->base + offset;
}

/* One loop's state, parameters and program while the kernel steps it. */
typedef struct {
    double a11, a12, a21, a22, b1, b2, friction, kp, kd, ki, kv, ka, kf, ko, cap, eo, fdir;
    double p, w, s, q, dac, r_prev, r_prev2;
    int has_prev, has_prev2, closed, tripped, stuck;
    const double *prog;
    Header header;
    double *x;
    Cursors cursors;
    long long tick, done, count, result;
    const double *modal;  /* the closed loop's modes (jump()), or NULL: step every tick */
    int n_modes;
    long long next_try, backoff;  /* when jump() is tried next, and how far it then waits */
} Loop;

static const double *modes_of(const double *k, Py_ssize_t k_len, int *n);

static void load(Loop *L, double *x, const double *k, Py_ssize_t k_len, const double *prog,
                 long long tick0, long long count)
{
    L->a11 = k[A11]; L->a12 = k[A12]; L->a21 = k[A21]; L->a22 = k[A22]; L->b1 = k[B1];
    L->b2 = k[B2]; L->friction = k[FRICTION]; L->kp = k[KP]; L->kd = k[KD]; L->ki = k[KI];
    L->kv = k[KV]; L->ka = k[KA]; L->kf = k[KF]; L->ko = k[KO]; L->cap = k[CAP];
    L->eo = k[EO]; L->fdir = k[FDIR];
    L->p = x[P]; L->w = x[W]; L->s = x[S]; L->q = x[Q]; L->dac = x[DAC];
    L->r_prev = x[RPREV]; L->r_prev2 = x[RPREV2];
    L->has_prev = x[HAS_PREV] != 0.0; L->has_prev2 = x[HAS_PREV2] != 0.0;
    L->closed = x[CLOSED] != 0.0; L->tripped = x[TRIPPED] != 0.0; L->stuck = x[STUCK] != 0.0;
    L->prog = prog;
    decode(&L->header, prog);
    L->x = x;
    L->cursors.phase = L->cursors.piece = L->cursors.segment = 0;
    L->tick = tick0;
    L->done = 0;
    L->count = count;
    L->result = count;
    L->modal = modes_of(k, k_len, &L->n_modes);
    L->next_try = tick0;
    L->backoff = JUMP_BACKOFF;
}

static void store(const Loop *L)
{
    double *x = L->x;
    x[P] = L->p; x[W] = L->w; x[S] = L->s; x[Q] = L->q; x[DAC] = L->dac;
    x[RPREV] = L->r_prev; x[RPREV2] = L->r_prev2;
    x[HAS_PREV] = L->has_prev; x[HAS_PREV2] = L->has_prev2; x[STUCK] = L->stuck;
}

/* One tick of one loop (the Python loop's body). 0: stepped; 1: the following error
 * tripped at this tick (not stepped: L->result says so). */
static ALWAYS_INLINE int once(Loop *L)
{
    double r_abs = commanded(L->prog, &L->header, L->tick, &L->cursors);
    double r = r_abs - L->eo;
    double v = L->has_prev ? r_abs - L->r_prev : 0.0;
    double v_prev = L->has_prev && L->has_prev2 ? L->r_prev - L->r_prev2 : 0.0;
    double a = v - v_prev;
    double p = L->p, w = L->w;
    double e = r - p;
    double u;
    if (L->tripped) {
        u = 0.0;
    } else if (!L->closed) {
        u = L->ko;
    } else {
        if (fabs(e) > FOLLOWING_ERROR_LIMIT) {
            L->result = -(L->done + 1);
            return 1;
        }
        double ki = L->ki, cap = L->cap, s = L->s;
        int held = L->stuck && fabs(e) < SETTLED_ERROR;
        double s_new = ki > 0 && !held ? s + e : ki > 0 ? s : 0.0;
        s_new = py_max(-cap, py_min(cap, s_new));
        double sign_v = v > 1e-12 ? 1.0 : v < -1e-12 ? -1.0 : 0.0;
        u = L->kp * e + L->kd * (e - L->q) + ki * s_new + L->kv * v + L->ka * a
            + L->kf * sign_v + L->ko;
        L->s = s_new;
        L->q = e;
    }
    u = py_max(-DAC_LIMIT, py_min(DAC_LIMIT, u));
    L->dac = u;
    L->r_prev2 = L->r_prev;
    L->has_prev2 = L->has_prev;
    L->r_prev = r_abs;
    L->has_prev = 1;
    L->tick++;
    L->done++;
    double friction = L->friction;
    if (L->stuck) {
        if (fabs(u) <= friction)
            return 0;
        L->stuck = 0;
    }
    double drive, w0 = w;
    if (friction != 0.0) {
        /* moving: friction opposes the motor; in drive terms that is fdir * sign(w),
         * fdir -1 when the output is inverted (SVP-: the plant's b terms negated) */
        double direction = w0 != 0.0 ? (w0 > 0 ? L->fdir : -L->fdir) : (u > 0 ? 1.0 : -1.0);
        drive = u - friction * direction;
        if (w0 == 0.0 && fabs(u) <= friction) {
            L->stuck = 1;
            return 0;
        }
    } else {
        drive = u;
    }
    double p_new = L->a11 * p + L->a12 * w0 + L->b1 * drive;
    double w_new = L->a21 * p + L->a22 * w0 + L->b2 * drive;
    if (friction != 0.0 && w0 != 0.0 && (w_new > 0) != (w0 > 0) && fabs(u) <= friction) {
        w_new = 0.0;
        L->stuck = 1;
    }
    L->p = p_new;
    L->w = w_new;
    return 0;
}

/* ---- the closed-form jump over a slew ------------------------------------------------
 *
 * While a profile slews or ramps linearly (the commanded position a polynomial of degree
 * at most 2 in the tick), the loop is
 * closed and linear (no saturation, the sum inside its cap, the motor moving one way so
 * friction is a constant force), its state has a closed form: per mode of the closed loop
 * (X' = A X + B [r, ff], diagonalised by servo.py's _Modal), z(j) = P0 + P1 j + P2 j^2
 * + delta lambda^j. jump() takes a whole phase (or what is left of it in this call) at
 * once, where a bound says the loop stays linear all the way (the particular part is a
 * polynomial, the
 * transient decays from |delta|); where it does not, the ticks are stepped and the jump
 * tried again a little later. Its result differs from stepping by rounding (about 1e-9
 * counts): the stepped ticks are the bit-exact twin of the Python loop, the jump is not
 * (tests/test_servo_kernel.py compares them with jumps switched off, and the jump against
 * stepping to a tolerance).
 *
 * The modes follow the parameters (servo_kernel.params): n, then lambda (n complex),
 * V (n x n), V^-1 (n x n), V^-1 B (n x 2), the output rows u, e, w, s (4 x n) and their
 * direct terms (4 x 2 real). Complex numbers are (re, im) pairs. */

typedef struct {
    double re, im;
} Cx;

static inline Cx cx(double re, double im) { Cx c = {re, im}; return c; }
static inline Cx cadd(Cx a, Cx b) { return cx(a.re + b.re, a.im + b.im); }
static inline Cx csub(Cx a, Cx b) { return cx(a.re - b.re, a.im - b.im); }
static inline Cx cmul(Cx a, Cx b) { return cx(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re); }
static inline Cx cscale(Cx a, double k) { return cx(a.re * k, a.im * k); }
static inline double cabs2(Cx a) { return hypot(a.re, a.im); }
static inline Cx cdiv(Cx a, Cx b)
{
    double d = b.re * b.re + b.im * b.im;
    return cx((a.re * b.re + a.im * b.im) / d, (a.im * b.re - a.re * b.im) / d);
}
/* lambda^j for a mode inside the unit circle (0 where it has decayed below any double) */
static inline Cx cpow_int(Cx lam, double j)
{
    double mag = cabs2(lam);
    if (mag == 0.0)
        return cx(j == 0.0 ? 1.0 : 0.0, 0.0);
    double r = exp(j * log(mag)), phi = j * atan2(lam.im, lam.re);
    return cx(r * cos(phi), r * sin(phi));
}

static Py_ssize_t modes_size(int n) { return 1 + 2 * n + 4 * n * n + 4 * n + 8 * n + 8; }

static const double *modes_of(const double *k, Py_ssize_t k_len, int *n)
{
    *n = 0;
    if (k_len < PARAM_SIZE + 1)
        return NULL;
    int m = (int)k[PARAM_SIZE];
    if ((m != 3 && m != 4) || k_len < PARAM_SIZE + modes_size(m))
        return NULL;
    *n = m;
    return k + PARAM_SIZE + 1;
}

enum { OUT_U, OUT_E, OUT_W, OUT_S, OUTPUTS };

/* Tick of a profile's time t (the commanded position's clock). */
static inline double time_of(const Header *h, long long tick)
{
    return (double)(tick - h->mstart) * h->period;
}

/* Try to take the ticks from L->tick to the end of its slew (or of this call) in closed
 * form: 1 if it did; 0 if not (then L->next_try says when to try again). */
static int jump(Loop *L)
{
    Header *h = &L->header;
    const double *prog = L->prog;
    long long T = L->tick, remaining = L->count - L->done;
    long long retry = T + L->backoff;
    if (h->kind != KIND_PROFILE || !L->closed || L->tripped) {
        L->next_try = NEVER;
        return 0;
    }
    if (h->has_mend && (double)T >= h->mend) {
        L->next_try = NEVER;
        return 0;
    }
    double t = time_of(h, T);
    if (prog[HAS_END_TIME] != 0.0 && t >= prog[END_TIME]) {
        L->next_try = NEVER;
        return 0;
    }
    if ((Py_ssize_t)prog[COUNT1] == 0) {
        L->next_try = NEVER;
        return 0;
    }
    double r_abs0 = h->base + profile_offset(prog, t, &L->cursors, &h->phase);
    const double *ph = h->phase.ph;
    /* where this phase (or the motion) ends: the first tick at or after it */
    double stop_t = h->phase.hi;
    if (prog[HAS_END_TIME] != 0.0 && prog[END_TIME] < stop_t)
        stop_t = prog[END_TIME];
    long long E = T + remaining;
    if (stop_t < HUGE_VAL) {
        double guess = ceil(stop_t / h->period);
        if (!(fabs(guess) < 4e15)) {
            L->next_try = NEVER;
            return 0;
        }
        long long e = h->mstart + (long long)guess;
        while (e > T && time_of(h, e - 1) >= stop_t)
            e--;
        while (time_of(h, e) < stop_t)
            e++;
        if (e < E)
            E = e;
    }
    if (h->has_mend && h->mend < (double)E)
        E = (long long)ceil(h->mend);
    int ramp = ph[PH_V1] != ph[PH_V2];
    if (ramp && (int)ph[PH_SHAPE] != SHAPE_LINEAR) {
        L->next_try = E;  /* not a polynomial of degree 2: stepped to its end */
        return 0;
    }
    if (L->stuck || !L->has_prev || !L->has_prev2) {
        L->next_try = retry;
        return 0;
    }
    double t2 = time_of(h, T - 2);
    if (!(t2 >= h->phase.lo && t2 >= ph[PH_T0])) {
        L->next_try = T + 2;  /* the history comes onto this phase in two ticks */
        return 0;
    }
    long long m = E - T;
    if (m < JUMP_MIN) {
        L->next_try = E;
        return 0;
    }
    Cursors c = L->cursors;
    Header hh = *h;
    long long mid = (m - 1) / 2;
    double r_abs1 = commanded(prog, &hh, T - 1, &c), r_abs2 = commanded(prog, &hh, T - 2, &c);
    double r_mid = commanded(prog, &hh, T + mid, &c);
    double r_last = commanded(prog, &hh, T + m - 1, &c);
    double r_last2 = commanded(prog, &hh, T + m - 2, &c);
    if (fabs(L->r_prev - r_abs1) > 1e-9 * py_max(1.0, fabs(r_abs1))
        || fabs(L->r_prev2 - r_abs2) > 1e-9 * py_max(1.0, fabs(r_abs2))) {
        L->next_try = retry;  /* the counters moved: step until the history is on it */
        return 0;
    }
    double friction = L->friction, w = L->w;
    if (friction != 0.0 && w == 0.0) {
        L->next_try = retry;
        return 0;
    }
    /* the inputs, polynomials in j: the commanded position r0 + r1 j + r2 j^2 (loop
     * frame; a line on a slew), through three of its exact values; its velocity
     * r(j) - r(j-1) and acceleration as the stepped loop takes them; friction constant */
    double jm = (double)mid, jl = (double)(m - 1), r1, r2;
    if (ramp) {
        double d1 = (r_mid - r_abs0) / jm, d2 = (r_last - r_mid) / (jl - jm);
        r2 = (d2 - d1) / jl;
        r1 = d1 - r2 * jm;
    } else {
        r2 = 0.0;
        r1 = (r_last - r_abs0) / jl;
    }
    double r0 = r_abs0 - L->eo;
    double v_first = r1 - r2, v_last = r1 - r2 + 2.0 * r2 * jl;
    if (!((v_first > 1e-9 && v_last > 1e-9) || (v_first < -1e-9 && v_last < -1e-9)
          || (!ramp && v_first == 0.0))) {
        L->next_try = retry;  /* the commanded velocity at or through zero */
        return 0;
    }
    double sign_v = v_first > 1e-12 ? 1.0 : v_first < -1e-12 ? -1.0 : 0.0;
    double fric = friction != 0.0 ? friction * (w > 0 ? L->fdir : -L->fdir) : 0.0;
    double ff0 = L->kv * v_first + L->ka * (2.0 * r2) + L->kf * sign_v + L->ko - fric;
    double ff1 = L->kv * (2.0 * r2);
    int n = L->n_modes;
    const double *md = L->modal;
    const Cx *lam = (const Cx *)md;
    const Cx *V = lam + n, *Vinv = V + n * n, *VB = Vinv + n * n, *G = VB + 2 * n;
    const double *DW = (const double *)(G + OUTPUTS * n);
    double X0[4];
    if (n == 4) {
        X0[0] = L->p; X0[1] = w; X0[2] = L->s; X0[3] = L->q;
    } else {
        X0[0] = L->p; X0[1] = w; X0[2] = L->q;
    }
    /* per mode z(j) = P0 + P1 j + P2 j^2 + delta lambda^j */
    Cx P0[4], P1[4], P2[4], delta[4];
    for (int i = 0; i < n; i++) {
        if (!(cabs2(lam[i]) < 1.0)) {
            L->next_try = NEVER;  /* not decaying: no bound */
            return 0;
        }
        Cx z0 = cx(0.0, 0.0);
        for (int j = 0; j < n; j++)
            z0 = cadd(z0, cscale(Vinv[i * n + j], X0[j]));
        Cx D0 = cadd(cscale(VB[2 * i], r0), cscale(VB[2 * i + 1], ff0));
        Cx D1 = cadd(cscale(VB[2 * i], r1), cscale(VB[2 * i + 1], ff1));
        Cx D2 = cscale(VB[2 * i], r2);
        Cx one_minus = csub(cx(1.0, 0.0), lam[i]);
        P2[i] = cdiv(D2, one_minus);
        P1[i] = cdiv(csub(D1, cscale(P2[i], 2.0)), one_minus);
        P0[i] = cdiv(csub(csub(D0, P1[i]), P2[i]), one_minus);
        delta[i] = csub(z0, P0[i]);
    }
    /* each checked output over j in [0, m]: a line plus a transient no larger than at j=0 */
    double mm = (double)m;
    double lows[OUTPUTS] = {-DAC_LIMIT, -FOLLOWING_ERROR_LIMIT, -HUGE_VAL, -L->cap};
    double highs[OUTPUTS] = {DAC_LIMIT, FOLLOWING_ERROR_LIMIT, HUGE_VAL, L->cap};
    if (friction != 0.0) {
        if (w > 0)
            lows[OUT_W] = 0.0;
        else
            highs[OUT_W] = 0.0;
    }
    for (int o = 0; o < OUTPUTS; o++) {
        if (o == OUT_S && (n == 3 || L->ki <= 0))
            continue;
        const Cx *g = G + o * n;
        double a0 = DW[2 * o] * r0 + DW[2 * o + 1] * ff0, a1 = DW[2 * o] * r1
            + DW[2 * o + 1] * ff1, a2 = DW[2 * o] * r2, bound = 0.0;
        if (o == OUT_U)
            a0 += fric;  /* the DAC's output: the friction is the plant's, not the filter's */
        for (int i = 0; i < n; i++) {
            a0 += cmul(g[i], P0[i]).re;
            a1 += cmul(g[i], P1[i]).re;
            a2 += cmul(g[i], P2[i]).re;
            bound += cabs2(g[i]) * cabs2(delta[i]);
        }
        double end = a0 + (a1 + a2 * mm) * mm;
        double lo = py_min(a0, end), hi = py_max(a0, end);
        if (a2 != 0.0) {
            double vertex = -a1 / (2.0 * a2);
            if (vertex > 0.0 && vertex < mm) {
                double at = a0 + (a1 + a2 * vertex) * vertex;
                lo = py_min(lo, at);
                hi = py_max(hi, at);
            }
        }
        /* a margin for the closed form's rounding against the stepped loop's */
        double slack = 1e-9 * (fabs(lo) + fabs(hi) + bound) + 1e-9;
        lo -= bound + slack;
        hi += bound + slack;
        if (!(lo > lows[o] && hi < highs[o])) {
            L->next_try = retry;
            L->backoff = L->backoff * 2 > JUMP_BACKOFF_MAX ? JUMP_BACKOFF_MAX : L->backoff * 2;
            return 0;
        }
    }
    /* the state m ticks on, and the output of the tick before */
    double X[4] = {0.0, 0.0, 0.0, 0.0}, u = 0.0;
    const Cx *gu = G + OUT_U * n;
    double before = mm - 1.0;
    for (int i = 0; i < n; i++) {
        Cx lm = cpow_int(lam[i], before);
        Cx z_before = cadd(cadd(P0[i], cscale(P1[i], before)),
                           cadd(cscale(P2[i], before * before), cmul(delta[i], lm)));
        Cx z = cadd(cadd(P0[i], cscale(P1[i], mm)),
                    cadd(cscale(P2[i], mm * mm), cmul(cmul(delta[i], lm), lam[i])));
        u += cmul(gu[i], z_before).re;
        for (int j = 0; j < n; j++)
            X[j] += cmul(V[j * n + i], z).re;
    }
    u += DW[2 * OUT_U] * (r0 + (r1 + r2 * before) * before)
        + DW[2 * OUT_U + 1] * (ff0 + ff1 * before) + fric;
    L->p = X[0];
    L->w = X[1];
    if (n == 4) {
        L->s = X[2];
        L->q = X[3];
    } else {
        L->q = X[2];
    }
    L->dac = py_max(-DAC_LIMIT, py_min(DAC_LIMIT, u));
    L->r_prev = r_last;
    L->r_prev2 = r_last2;
    L->tick += m;
    L->done += m;
    L->next_try = L->tick;
    L->backoff = JUMP_BACKOFF;
    return 1;
}

/* One tick, or a jump where one is due (each loop's ticks are the same either way) */
static ALWAYS_INLINE int advance_loop(Loop *L)
{
    if (L->modal != NULL && L->tick >= L->next_try && L->count - L->done >= JUMP_MIN
        && jump(L))
        return 0;
    return once(L);
}

/* Step one loop `count` ticks: the ticks stepped, or -(ticks + 1) on a trip. */
static long long run(double *x, const double *k, Py_ssize_t k_len, const double *prog,
                     long long tick0, long long count)
{
    Loop L;
    load(&L, x, k, k_len, prog, tick0, count);
    while (L.done < count)
        if (advance_loop(&L))
            break;
    store(&L);
    return L.result;
}

/* Step several loops, one tick of each in turn: their ticks are independent, so the
 * processor overlaps one loop's arithmetic with another's, where one loop alone waits on
 * each result (about 12% faster over a board's ten axes). Each loop's own arithmetic is
 * run()'s, in its order: the results are the same bits. */
static void run_many(Loop *loops, Py_ssize_t n)
{
    for (;;) {
        int any = 0;
        for (Py_ssize_t i = 0; i < n; i++) {
            Loop *L = &loops[i];
            if (L->done < L->count) {
                any = 1;
                if (advance_loop(L))
                    L->count = L->done;  /* tripped: no more ticks */
            }
        }
        if (!any)
            break;
    }
    for (Py_ssize_t i = 0; i < n; i++)
        store(&loops[i]);
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
    case KIND_CONTOUR_JERK:
        return n2 < 1 ? -1 : HEADER + n1 * JERK_PIECE_SIZE + n2 * SEGMENT_SIZE;
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
        result = run(state.buf, params.buf, params.len / (Py_ssize_t)sizeof(double), prog, tick,
                     count);
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

/* A loop step_axes steps: its Python object and the buffers it holds while it runs. */
typedef struct {
    PyObject *loop;
    Py_buffer state, params, program;
    int have_state, have_params, have_program;
} Job;

static void release(Job *job)
{
    if (job->have_state)
        PyBuffer_Release(&job->state);
    if (job->have_params)
        PyBuffer_Release(&job->params);
    if (job->have_program)
        PyBuffer_Release(&job->program);
    job->have_state = job->have_params = job->have_program = 0;
    Py_CLEAR(job->loop);
}

/* 1: `loop` (with its buffers) is ready for the kernel from `*tick`; 2: nothing to
 * step (already at `limit`); 0: not for the kernel (left to Python); -1: an error */
static int prepare(PyObject *axis, long long limit, Job *job, long long *tick)
{
    int result = 0;
    PyObject *fast = NULL, *attr = NULL;
    job->loop = PyObject_GetAttr(axis, s_servo);
    if (job->loop == NULL)
        return -1;
    PyObject *loop = job->loop;
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
    *tick = PyLong_AsLongLong(attr);
    Py_CLEAR(attr);
    if (*tick == -1 && PyErr_Occurred()) {
        result = -1;
        goto done;
    }
    if (*tick >= limit) {
        result = 2;
        goto done;
    }
    attr = PyObject_GetAttr(loop, s_x);
    if (attr == NULL) {
        result = -1;
        goto done;
    }
    if (get_doubles(attr, &job->state, 1, STATE_SIZE, "state") < 0) {
        result = -1;
        goto done;
    }
    job->have_state = 1;
    if (get_doubles(PyTuple_GET_ITEM(kernel, 0), &job->params, 0, PARAM_SIZE, "params") < 0) {
        result = -1;
        goto done;
    }
    job->have_params = 1;
    if (get_doubles(PyTuple_GET_ITEM(kernel, 1), &job->program, 0, HEADER, "program") < 0) {
        result = -1;
        goto done;
    }
    job->have_program = 1;
    Py_ssize_t size = program_size(job->program.buf,
                                   job->program.len / (Py_ssize_t)sizeof(double));
    if (size < 0 || size > job->program.len / (Py_ssize_t)sizeof(double)) {
        PyErr_SetString(PyExc_ValueError, "program: not a motion's description");
        result = -1;
        goto done;
    }
    result = 1;
done:
    Py_XDECREF(attr);
    Py_XDECREF(fast);
    if (result != 1)
        release(job);
    return result;
}

/* Write back where a stepped loop stands: its tick, and its trip tick on a trip. */
static int finish(Job *job, const Loop *L)
{
    long long stepped = L->result;
    long long reached = L->tick;
    PyObject *value = PyLong_FromLongLong(reached);
    int failed = value == NULL || PyObject_SetAttr(job->loop, s_tick, value) < 0
        || (stepped < 0 && PyObject_SetAttr(job->loop, s_trip_tick, value) < 0);
    Py_XDECREF(value);
    return failed ? -1 : 0;
}

#define MAX_JOBS 64  /* loops stepped together; more wait for the next round */

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
    Job jobs[MAX_JOBS];
    Loop loops[MAX_JOBS];
    Py_ssize_t n = PySequence_Fast_GET_SIZE(axes), i = 0;
    int failed = 0;
    while (i < n && !failed) {
        Py_ssize_t m = 0;
        for (; i < n && m < MAX_JOBS; i++) {
            PyObject *axis = PySequence_Fast_GET_ITEM(axes, i);
            Job *job = &jobs[m];
            memset(job, 0, sizeof(*job));
            long long tick = 0;
            int ready = prepare(axis, limit, job, &tick);
            if (ready < 0 || (ready == 0 && PyList_Append(rest, axis) < 0)) {
                failed = 1;
                break;
            }
            if (ready == 1) {
                load(&loops[m], job->state.buf, job->params.buf,
                     job->params.len / (Py_ssize_t)sizeof(double), job->program.buf, tick,
                     limit - tick);
                m++;
            }
        }
        if (!failed)
            run_many(loops, m);
        for (Py_ssize_t j = 0; j < m; j++) {
            if (!failed && finish(&jobs[j], &loops[j]) < 0)
                failed = 1;
            release(&jobs[j]);
        }
    }
    Py_DECREF(axes);
    if (failed) {
        Py_DECREF(rest);
        return NULL;
    }
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
