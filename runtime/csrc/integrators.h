/* Generic ODE integrators over the generated model functions (thesis 3.1).
 *
 * Every generated model function has the one signature
 *     void NAME(const double *in, const double *p, double *out);
 * (docs/INTERFACES.md).  The systems are autonomous: d state/dt = rhs(state, p).
 *
 * Methods (lev_integrate's `method`):
 *   LEV_EULER        explicit Euler, fixed step                      (thesis 3.1.2)
 *   LEV_RK4          classical Runge-Kutta 4, fixed step             (thesis 3.1.3-3.1.4)
 *   LEV_DOP853       Dormand-Prince 8(5,3), adaptive, dense output   (Hairer, Norsett, Wanner I, II.10)
 *   LEV_GAUSS4       2-stage Gauss-Legendre collocation, order 4, symplectic, fixed step
 *   LEV_MIDPOINT     implicit midpoint rule (1-stage Gauss), order 2, symplectic, fixed step
 *   LEV_DOP853_FIXED the 8th-order DOP853 formula at a fixed step (for order tests)
 *   LEV_VERN9        Verner's "most efficient" 9(8) pair, adaptive, dense output of order 9
 *                    (a Verner step of theta h from the start of the step; Numer. Algor. 53, 2010)
 *   LEV_TAYLOR       Taylor's method over the generated coefficients (sys->taylor), order and
 *                    step from the tolerance (Jorba & Zou, Experiment. Math. 14, 2005), dense
 *                    output the step's own polynomial
 *
 * Every method updates the state by compensated summation (Kahan): a step's increment is tiny
 * against a state that grows (the spin angle), and the rounding of x + increment would otherwise
 * random-walk into the result (about 2e-13 of the bench's error measure over 32 spin periods).
 *
 * Thread safety: there is no global mutable state.  All memory is provided by the caller
 * (`work`, of lev_work_bytes(method, n) bytes, 16-byte aligned; the output buffers), so any
 * number of runs may proceed concurrently on different buffers.
 */
#ifndef LEVITRON_INTEGRATORS_H
#define LEVITRON_INTEGRATORS_H

#include <stddef.h>

typedef void (*lev_fn)(const double *in, const double *p, double *out);

/* A generated Taylor function (derive/emit/taylor.py): out[k (order + 1) + j] = the j-th Taylor
 * coefficient of state k of the solution through `in`; 0, or -1 for an order out of range. */
typedef int (*lev_taylor_fn)(const double *in, const double *p, int order, double *out);

/* The largest order LEV_TAYLOR asks for (the generated functions hold as many: model.h) */
#define LEV_TAYLOR_MAX_ORDER 32

enum lev_method {
    LEV_EULER = 0,
    LEV_RK4 = 1,
    LEV_DOP853 = 2,
    LEV_GAUSS4 = 3,
    LEV_MIDPOINT = 4,
    LEV_DOP853_FIXED = 5,
    LEV_VERN9 = 6,
    LEV_TAYLOR = 7
};

enum lev_status {
    LEV_COMPLETED = 0,       /* reached t_end */
    LEV_LEFT_BOX = 1,        /* the state left the box (event); x is the state at the exit */
    LEV_NONFINITE = 2,       /* the right-hand side produced inf/nan; x is the last finite state */
    LEV_STEP_UNDERFLOW = 3,  /* the adaptive step fell below 10 ulp of t */
    LEV_STEP_BUDGET = 4,     /* the step budget (max_steps attempted steps) ran out before t_end */
    LEV_NO_CONVERGENCE = 5,  /* the implicit stage equations did not converge */
    LEV_BAD_INPUT = 6,       /* invalid options (see lev_status_message) */
    LEV_ENERGY_LIMIT = 7     /* the energy drifted beyond opt->energy_limit (relative) */
};

typedef struct {
    int n;              /* state dimension */
    lev_fn rhs;         /* d state/dt, n -> n */
    lev_fn jac;         /* d rhs/d state, row-major n x n; NULL: fixed-point iteration (gauss) */
    lev_fn energy;      /* a scalar invariant monitored after every step; NULL: none */
    const double *p;    /* parameter vector passed to every call */
    lev_taylor_fn taylor; /* LEV_TAYLOR: the Taylor coefficients; NULL: none */
    lev_fn quad;        /* a quadrature: the last of the n states is W with dW/dt = quad(state, p)
                           (one value; rhs gives the other n - 1 rates and reads none of W), so W
                           is integrated inside the run by the method's own stages and dense
                           output, left out of the adaptive error norm so that it does not steer
                           the steps (the work of air friction, runtime/physics/friction.py);
                           jac, if given, is then the (n - 1) x (n - 1) one of rhs, and LEV_TAYLOR
                           and lev_integrate_lanes refuse it; NULL: none */
} lev_system;

typedef struct {
    double t0, t_end;
    double h;           /* fixed step (rounded so that an integer number of steps ends at t_end);
                           DOP853: first step, 0 = automatic */
    double rtol, atol;  /* DOP853 local error control: |err_k| <= atol_k + rtol |x_k| (RMS norm);
                           LEV_TAYLOR: order and step from rtol (> 0), atol_k / rtol the floor of
                           each component's magnitude */
    const double *atol_v; /* per-component absolute tolerances (n), or NULL: atol for all */
    double h_max;       /* DOP853 largest step; 0 = unlimited */
    long max_steps;     /* the step budget: attempted steps (accepted + rejected), > 0 required */
    int box_on;         /* 1: stop when the state leaves the box */
    int ix, iy, iz;     /* indices of x, y, z in the state; -1 if absent */
    double z_lo, z_hi;  /* the box in z (absolute heights) */
    double r_max;       /* the box radially: sqrt(x^2 + y^2) <= r_max (inf disables) */
    const double *t_out;/* DOP853: record samples at these ascending times (dense output); or NULL */
    long n_out;
    long every;         /* otherwise: record every `every`-th step (and the first and last state) */
    long max_samples;   /* capacity of out_t (max_samples) and out_x (max_samples * n) */
    int max_iter;       /* implicit methods: iteration limit per step, 0 = default */
    double energy_limit;/* > 0 (needs sys->energy): stop once |H - H0| > energy_limit |H0| */
} lev_options;

typedef struct {
    int status;
    long steps;          /* accepted steps */
    long rejected;       /* rejected steps (DOP853) */
    long rhs_evals;
    long jac_evals;
    long energy_evals;
    long iterations;     /* implicit methods: total Newton / fixed-point iterations */
    long n_samples;      /* samples written */
    long dropped;        /* samples that did not fit into the buffers */
    double t_final;      /* time of the returned state */
    double h_last;       /* the last step size used */
    double energy0;      /* energy at t0 (if monitored) */
    double energy_max_dev; /* max |H(t) - H(t0)| over all accepted steps */
} lev_stats;

/* out[r * n_out ..] = f(in[r * n_in ..], p) for r = 0 .. rows - 1: a generated function over the
 * samples of a trajectory in one call (the invariants of a run, runtime/model/load.py Model.rows). */
void lev_rows(lev_fn f, long rows, int n_in, int n_out, const double *in, const double *p,
              double *out);

/* Bytes of `work` that lev_integrate needs for this method and dimension. */
size_t lev_work_bytes(int method, int n);

/* Integrate from opt->t0 to opt->t_end.  x: initial state in, final state out.
 * out_t / out_x / out_e (may be NULL) receive the samples; returns st->status. */
int lev_integrate(int method, const lev_system *sys, const lev_options *opt, double *x,
                  void *work, double *out_t, double *out_x, double *out_e, lev_stats *st);

/* lev_integrate's arguments in one struct: a caller that runs the same system again and again
 * (runtime/integrate/propagator.py) builds it once and passes one pointer per run. */
typedef struct {
    int method;
    const lev_system *sys;
    const lev_options *opt;
    double *x;
    void *work;
    double *out_t, *out_x, *out_e;
    lev_stats *st;
} lev_job;

/* lev_integrate(job->method, job->sys, ...): the same run. */
int lev_integrate_job(const lev_job *job);

/* The largest state dimension (the scratch sums of the explicit methods live on the stack). */
#define LEV_MAX_STATES 256

/* ---- several runs at once through a lane variant of the rhs (the scan driver) ----
 *
 * The generated model has, beside each `<part>_rhs`, `<part>_rhs_lanes`: the same statements for
 * LEV_LANES trajectories at once (lane l reads in[k LEV_LANES + l], p[k LEV_LANES + l] and writes
 * out[k LEV_LANES + l]), in a loop the compiler vectorises, so that one call costs about what one
 * scalar call does (derive/emit/c). lev_integrate_lanes runs `count` adaptive runs (DOP853 or
 * Vern9), each exactly as lev_integrate would (the same numbers; no samples), keeping LEV_LANES
 * of them under way and making each stage's evaluations of all of them in one rhs_lanes call; a
 * lane whose run ends takes the next.
 *
 *   setup(user, k, sys, opt, x)   fills run k's system, options and state (sys and opt arrive
 *                                 zeroed; sys->n = n, sys->p n_p values); nonzero: the run is
 *                                 reported as LEV_BAD_INPUT. Pointers it stores must stay valid
 *                                 until done(k).
 *   done(user, k, status, st, x)  run k's status, statistics and final state; runs end in no
 *                                 particular order.
 *   work                          lev_lanes_work_bytes(method, n) bytes, 16-byte aligned.
 * Returns count, or -1 for invalid arguments (nothing run). */
#define LEV_LANES 4

typedef int (*lev_batch_setup)(void *user, long k, lev_system *sys, lev_options *opt, double *x);
typedef void (*lev_batch_done)(void *user, long k, int status, const lev_stats *st,
                               const double *x);

size_t lev_lanes_work_bytes(int method, int n);
long lev_integrate_lanes(int method, int n, int n_p, lev_fn rhs_lanes, long count,
                         lev_batch_setup setup, lev_batch_done done, void *user, void *work);

/* A one-line message for a status code. */
const char *lev_status_message(int status);

/* The method table (runtime/integrate/methods.py holds the same; tests compare the two):
 * the enum value of a method name (-1 if unknown), the name of an enum value (NULL if unknown),
 * and 1 if the method takes a fixed step, 0 if adaptive, -1 if unknown. */
int lev_method_id(const char *name);
const char *lev_method_name(int method);
int lev_method_fixed_step(int method);

/* The order LEV_TAYLOR uses for a tolerance: ceil(-ln(rtol) / 2 + 1), within 2 .. LEV_TAYLOR_MAX_ORDER. */
int lev_taylor_order(double rtol);

/* sizeof of the structs passed through ctypes (runtime/integrate/c_backend.py checks its mirrors). */
size_t lev_sizeof_system(void);
size_t lev_sizeof_options(void);
size_t lev_sizeof_stats(void);
size_t lev_sizeof_job(void);

/* Nanoseconds per call of f(x, p, out) measured in C over `reps` calls (clock_gettime). */
double lev_time_fn(lev_fn f, const double *x, const double *p, int n_out, long reps);

#endif
