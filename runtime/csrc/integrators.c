/* Generic ODE integrators over the generated model functions; see integrators.h.
 *
 * Euler (thesis 3.1.2) and classical Runge-Kutta 4 (thesis 3.1.3-3.1.4) at a fixed step;
 * Dormand-Prince 8(5,3) with the step-size control, error norm and 7th-degree dense output of
 * Hairer's dop853 (coefficients as in scipy.integrate._ivp.dop853_coefficients, exact doubles);
 * Verner's "most efficient" 9(8) pair (Numer. Algor. 53, 2010) under the same driver
 * (run_adaptive), its dense output a Verner step of theta h (order 9, 15 evaluations per point);
 * s-stage Gauss-Legendre collocation (s = 1: implicit midpoint, s = 2: order 4), symplectic,
 * with the stage equations solved to round-off by simplified Newton (generated Jacobian) or by
 * fixed-point iteration, and compensated summation of the state update.
 *
 * No global mutable state: every buffer is provided by the caller.
 */
#define _POSIX_C_SOURCE 199309L
#include "integrators.h"

#include <float.h>
#include <math.h>
#include <string.h>
#include <time.h>

/* integrators.c is one translation unit (the compiler inlines the stages and the drivers across
 * methods, as it did when they were one file); each idea is its own fragment (integrators_*.c.h:
 * named .c.h, not .h, for it is a piece of this file, not a header; README.md), included here
 * once and in this order. */
#define LEV_INTEGRATORS_TU

#include "integrators_tableaus.c.h"

/* ---- bookkeeping shared by all methods ---- */

typedef struct {
    const lev_system *sys;
    const lev_options *opt;
    lev_stats *st;
    double *out_t, *out_x, *out_e;
    double t_last_rec;  /* time of the last recorded sample (avoids duplicates) */
    int recorded_any;
} lev_ctx;

static void call_rhs(lev_ctx *c, const double *x, double *out)
{
    const lev_system *s = c->sys;
    s->rhs(x, s->p, out);
    if (s->quad) s->quad(x, s->p, out + s->n - 1);   /* dW/dt: the quadrature, the last state */
    c->st->rhs_evals++;
}

/* The components an adaptive step's error norm takes: all but a quadrature (lev_system.quad). */
static int normed(const lev_system *s)
{
    return s->quad ? s->n - 1 : s->n;
}

static double call_energy(lev_ctx *c, const double *x)
{
    double e = 0.0;
    c->sys->energy(x, c->sys->p, &e);
    c->st->energy_evals++;
    return e;
}

static int all_finite(const double *x, int n)
{
    int k;
    for (k = 0; k < n; k++)
        if (!isfinite(x[k])) return 0;
    return 1;
}

/* 1 iff the state is outside the box: z below z_lo or above z_hi, or sqrt(x^2 + y^2) > r_max
 * (compared squared: no hypot call on every step). */
static int box_outside(const lev_options *o, const double *x)
{
    if (o->iz >= 0 && (x[o->iz] > o->z_hi || x[o->iz] < o->z_lo)) return 1;
    if (isfinite(o->r_max) && (o->ix >= 0 || o->iy >= 0)) {
        const double a = o->ix >= 0 ? x[o->ix] : 0.0, b = o->iy >= 0 ? x[o->iy] : 0.0;
        return a * a + b * b > o->r_max * o->r_max;
    }
    return 0;
}

static int outside(const lev_options *o, const double *x)
{
    return o->box_on && box_outside(o, x);
}

static void record(lev_ctx *c, double t, const double *x, double e)
{
    int n = c->sys->n;
    lev_stats *st = c->st;
    if (c->recorded_any && t == c->t_last_rec) return;
    if (st->n_samples >= c->opt->max_samples || !c->out_x || !c->out_t) {
        st->dropped++;
        return;
    }
    c->out_t[st->n_samples] = t;
    memcpy(c->out_x + (size_t)st->n_samples * (size_t)n, x, (size_t)n * sizeof(double));
    if (c->out_e) c->out_e[st->n_samples] = e;
    st->n_samples++;
    c->t_last_rec = t;
    c->recorded_any = 1;
}

/* energy bookkeeping after an accepted step; returns the energy (0 if not monitored) */
static double monitor(lev_ctx *c, const double *x)
{
    double e, d;
    if (!c->sys->energy) return 0.0;
    e = call_energy(c, x);
    d = fabs(e - c->st->energy0);
    if (d > c->st->energy_max_dev || !isfinite(d)) c->st->energy_max_dev = d;
    return e;
}

static int energy_exceeded(const lev_ctx *c)
{
    return c->opt->energy_limit > 0.0 && c->sys->energy
        && !(c->st->energy_max_dev <= c->opt->energy_limit * fabs(c->st->energy0));
}

const char *lev_status_message(int status)
{
    switch (status) {
    case LEV_COMPLETED: return "completed: reached t_end";
    case LEV_LEFT_BOX: return "stopped: the state left the box";
    case LEV_NONFINITE: return "stopped: the right-hand side became non-finite (inf/nan)";
    case LEV_STEP_UNDERFLOW: return "stopped: the adaptive step size underflowed";
    case LEV_STEP_BUDGET: return "stopped: the step budget (max_steps) ran out before t_end";
    case LEV_NO_CONVERGENCE: return "stopped: the implicit stage equations did not converge";
    case LEV_BAD_INPUT: return "invalid input: check n, step, tolerances, buffers and t_out";
    case LEV_ENERGY_LIMIT: return "stopped: the energy drifted beyond the requested limit";
    default: return "unknown status";
    }
}

/* ---- the method table and the struct sizes (checked against runtime/integrate/methods.py) ---- */

static const char *const METHOD_NAMES[] = {"euler", "rk4", "dop853", "gauss4", "midpoint",
                                           "dop853-fixed", "vern9", "taylor"};
#define LEV_N_METHODS ((int)(sizeof METHOD_NAMES / sizeof METHOD_NAMES[0]))

int lev_method_id(const char *name)
{
    int k;
    if (!name) return -1;
    for (k = 0; k < LEV_N_METHODS; k++)
        if (strcmp(name, METHOD_NAMES[k]) == 0) return k;
    return -1;
}

const char *lev_method_name(int method)
{
    return (method >= 0 && method < LEV_N_METHODS) ? METHOD_NAMES[method] : NULL;
}

int lev_method_fixed_step(int method)
{
    if (method < 0 || method >= LEV_N_METHODS) return -1;
    return method != LEV_DOP853 && method != LEV_VERN9 && method != LEV_TAYLOR;
}

size_t lev_sizeof_system(void) { return sizeof(lev_system); }
size_t lev_sizeof_options(void) { return sizeof(lev_options); }
size_t lev_sizeof_stats(void) { return sizeof(lev_stats); }
size_t lev_sizeof_job(void) { return sizeof(lev_job); }

/* ---- work layout ---- */

/* Work of an adaptive run (adaptive_start): K (17 n), xn, f, tmp, F (7 n), yd, yo, f1, comp,
 * comp_new, P. */
#define ADAPTIVE_WORK 33

static size_t gauss_stages(int method) { return method == LEV_MIDPOINT ? 1u : 2u; }

void lev_rows(lev_fn f, long rows, int n_in, int n_out, const double *in, const double *p,
              double *out)
{
    for (long r = 0; r < rows; ++r)
        f(in + r * n_in, p, out + r * n_out);
}

size_t lev_work_bytes(int method, int n)
{
    size_t N = (size_t)(n > 0 ? n : 1), s, m;
    switch (method) {
    /* fixed steps: xn, comp, comp_new, slope, then the method's own (run_fixed) */
    case LEV_EULER: return 4 * N * sizeof(double);
    case LEV_RK4: return 9 * N * sizeof(double);
    case LEV_DOP853_FIXED: return 17 * N * sizeof(double);
    case LEV_DOP853:
    case LEV_VERN9: return ADAPTIVE_WORK * N * sizeof(double);
    /* the coefficients (LEV_TAYLOR_MAX_ORDER + 1 per state), xn, comp, comp_new, yd, inc */
    case LEV_TAYLOR: return ((size_t)(LEV_TAYLOR_MAX_ORDER + 1) * N + 5 * N) * sizeof(double);
    case LEV_GAUSS4:
    case LEV_MIDPOINT:
        s = gauss_stages(method);
        m = s * N;
        /* Z, Zprev, F, dZ, G (5 m), Y, comp, xnew (3 N), J (N^2), M (m^2); pivots (m ints) */
        return (5 * m + 3 * N + N * N + m * m) * sizeof(double) + m * sizeof(int) + 16;
    default: return 0;
    }
}

#include "integrators_rk_stages.c.h"

#include "integrators_dop853_vern9.c.h"

#include "integrators_fixed.c.h"

#include "integrators_adaptive.c.h"

#include "integrators_taylor.c.h"

#include "integrators_gauss.c.h"

/* ---- driver ---- */

/* lev_integrate's checks and its first sample: LEV_RUNNING, or the status of a run that ends here
 * (st->status set).  c is filled for the method's loop. */
static int integrate_begin(int method, const lev_system *sys, const lev_options *opt, double *x,
                           void *work, double *out_t, double *out_x, double *out_e, lev_stats *st,
                           lev_ctx *c)
{
    int fixed, n;
    double e0 = 0.0;

    if (!st) return LEV_BAD_INPUT;
    memset(st, 0, sizeof *st);
    st->t_final = opt ? opt->t0 : 0.0;
    st->status = LEV_BAD_INPUT;
    if (!sys || !opt || !x || !work || !sys->rhs || sys->n <= 0 || sys->n > LEV_MAX_STATES)
        return LEV_BAD_INPUT;
    n = sys->n;
    fixed = lev_method_fixed_step(method);
    if (fixed < 0) return LEV_BAD_INPUT;
    if (opt->max_steps <= 0) return LEV_BAD_INPUT;      /* every run has a step budget */
    if (!(opt->t_end > opt->t0) || !isfinite(opt->t0) || !isfinite(opt->t_end)) return LEV_BAD_INPUT;
    if (fixed && (!(opt->h > 0.0) || !isfinite(opt->h))) return LEV_BAD_INPUT;
    if (fixed && opt->t_out) return LEV_BAD_INPUT;
    if (method == LEV_TAYLOR && (!sys->taylor || !(opt->rtol > 0.0) || sys->quad)) return LEV_BAD_INPUT;
    if (sys->quad && n < 2) return LEV_BAD_INPUT;
    if (!fixed && (!(opt->rtol >= 0.0) || !(opt->atol >= 0.0) || !(opt->h >= 0.0)
                   || !(opt->h_max >= 0.0)))
        return LEV_BAD_INPUT;
    if (!fixed) {
        int k;
        for (k = 0; k < n; k++) {
            double a = opt->atol_v ? opt->atol_v[k] : opt->atol;
            if (!(a >= 0.0) || !isfinite(a) || !(a + opt->rtol > 0.0)) return LEV_BAD_INPUT;
        }
    }
    if (opt->max_samples < 0 || (opt->box_on && (opt->iz >= n || opt->ix >= n || opt->iy >= n)))
        return LEV_BAD_INPUT;
    if (!all_finite(x, n)) return LEV_BAD_INPUT;

    c->sys = sys;
    c->opt = opt;
    c->st = st;
    c->out_t = out_t;
    c->out_x = out_x;
    c->out_e = out_e;
    c->t_last_rec = 0.0;
    c->recorded_any = 0;

    if (sys->energy) {
        e0 = call_energy(c, x);
        st->energy0 = e0;
    }
    if (!opt->t_out) record(c, opt->t0, x, e0);
    if (outside(opt, x)) {
        st->status = LEV_LEFT_BOX;
        return st->status;
    }
    return LEV_RUNNING;
}

/* The last sample of a run that went through its method's loop; st->status. */
static int integrate_end(lev_ctx *c, double *x, int status)
{
    const lev_system *sys = c->sys;
    if (!c->opt->t_out || status != LEV_COMPLETED)
        record(c, c->st->t_final, x, sys->energy ? call_energy(c, x) : 0.0);
    c->st->status = status;
    return status;
}

int lev_integrate(int method, const lev_system *sys, const lev_options *opt, double *x,
                  void *work, double *out_t, double *out_x, double *out_e, lev_stats *st)
{
    lev_ctx c;
    int status = integrate_begin(method, sys, opt, x, work, out_t, out_x, out_e, st, &c);
    if (status != LEV_RUNNING) return status;
    if (method == LEV_DOP853)
        status = run_adaptive(&c, x, (double *)work, &DOP853_M);
    else if (method == LEV_VERN9)
        status = run_adaptive(&c, x, (double *)work, &VERN9_M);
    else if (method == LEV_TAYLOR)
        status = run_taylor(&c, x, (double *)work);
    else if (method == LEV_GAUSS4 || method == LEV_MIDPOINT)
        status = run_gauss(method, &c, x, (double *)work);
    else
        status = run_fixed(method, &c, x, (double *)work);
    return integrate_end(&c, x, status);
}

int lev_integrate_job(const lev_job *job)
{
    if (!job) return LEV_BAD_INPUT;
    return lev_integrate(job->method, job->sys, job->opt, job->x, job->work, job->out_t, job->out_x,
                         job->out_e, job->st);
}

#include "integrators_lanes.c.h"

/* ---- timing ---- */

double lev_time_fn(lev_fn f, const double *x, const double *p, int n_out, long reps)
{
    double out[4096];
    struct timespec a, b;
    long r;
    volatile double sink;
    if (n_out < 1 || n_out > 4096 || reps < 1 || !f) return -1.0;
    clock_gettime(CLOCK_MONOTONIC, &a);
    for (r = 0; r < reps; r++) f(x, p, out);
    clock_gettime(CLOCK_MONOTONIC, &b);
    sink = out[0];
    (void)sink;
    return ((double)(b.tv_sec - a.tv_sec) * 1e9 + (double)(b.tv_nsec - a.tv_nsec)) / (double)reps;
}
