/* the adaptive driver that DOP853 and Verner 9(8) share (start, next, stages, judge).
 * Part of integrators.c's translation unit: included there once, nowhere else. */
#ifndef LEV_INTEGRATORS_TU
#error "integrators_adaptive.c.h is part of integrators.c: include it only there"
#endif

/* ---- the adaptive driver ---- */

/* One adaptive run between step attempts (run_adaptive: start, then per attempt next, the
 * stages, judge). */
typedef struct {
    lev_ctx *c;
    const adaptive_method *m;
    double *x;                       /* the state: the caller's buffer */
    double *K, *xn, *f, *tmp, *F, *yd, *yo, *f1, *comp, *comp_new, *P;
    double t, t_new, h, h_abs, hmax;
    double err, fac;                 /* the attempt's error estimate and step factor */
    long i_out;
    int rejected_here, last_nonfinite;
} adaptive_run;

#define LEV_RUNNING (-1)


/* The first evaluation, the first step size and the samples at t0; LEV_RUNNING or a status. */
static int adaptive_start(adaptive_run *r, lev_ctx *c, double *x, double *w,
                          const adaptive_method *m)
{
    const lev_options *o = c->opt;
    int i, n = c->sys->n;
    double span = o->t_end - o->t0;
    r->c = c;
    r->m = m;
    r->x = x;
    r->K = w;
    r->xn = w + 17 * n;
    r->f = w + 18 * n;
    r->tmp = w + 19 * n;
    r->F = w + 20 * n;
    r->yd = w + 27 * n;
    r->yo = w + 28 * n;
    r->f1 = w + 29 * n;
    r->comp = w + 30 * n;
    r->comp_new = w + 31 * n;
    r->P = w + 32 * n;
    r->t = o->t0;
    r->h = 0.0;
    r->i_out = 0;
    r->rejected_here = r->last_nonfinite = 0;
    for (i = 0; i < n; i++) r->comp[i] = 0.0;
    call_rhs(c, x, r->f);
    if (!all_finite(r->f, n)) return LEV_NONFINITE;
    r->hmax = o->h_max > 0.0 ? o->h_max : span;
    r->h_abs = o->h > 0.0 ? o->h : dp_initial_step(c, x, r->f, span, r->hmax, r->tmp, r->f1);
    if (r->h_abs > r->hmax) r->h_abs = r->hmax;
    while (o->t_out && r->i_out < o->n_out && o->t_out[r->i_out] <= r->t) {
        record(c, r->t, x, c->st->energy0);
        r->i_out++;
    }
    return LEV_RUNNING;
}

/* Before an attempt: the step size, the budget; K[0] = rhs(x).  LEV_RUNNING or a status. */
static int adaptive_next(adaptive_run *r)
{
    const lev_options *o = r->c->opt;
    lev_stats *st = r->c->st;
    double t_new;
    /* the step may not fall below 10 ulp of t (nextafter, a libm call, only when it could) */
    if (!(r->h_abs > 1e-13 * fabs(r->t) && r->h_abs > 1e-300)
        && r->h_abs < 10.0 * (nextafter(r->t, INFINITY) - r->t))
        return r->last_nonfinite ? LEV_NONFINITE : LEV_STEP_UNDERFLOW;
    if (st->steps + st->rejected >= o->max_steps) return LEV_STEP_BUDGET;
    t_new = r->t + r->h_abs;
    if (t_new > o->t_end) t_new = o->t_end;
    r->t_new = t_new;
    r->h = t_new - r->t;
    memcpy(r->K, r->f, (size_t)r->c->sys->n * sizeof(double));
    memset(r->P, 0, (size_t)r->c->sys->n * sizeof(double));    /* stage 1 has no older stage */
    return LEV_RUNNING;
}

/* Stage s (1 <= s < stages) of the attempt, or for s == stages the solution xn (compensated),
 * its error estimate and K[f_slot] = rhs(xn).
 *
 * Only the newest stage is on the critical path: the sum over the older stages (P) for the next
 * combination is formed before this stage's rhs is called, so that the processor computes it
 * while the rhs runs; the error estimate likewise precedes rhs(xn).  The sums are the plain
 * sums, term for term in the same order (rk_sum_n), so the result is the same bit for bit. */
LEV_FORCE_INLINE const double *adaptive_stage_arg(adaptive_run *r, int s, const adaptive_method *m,
                                                  const int n, double **dst)
{
    const lev_options *o = r->c->opt;
    const int last = s == m->stages;
    const double *row = last ? m->B : m->A[s], *Knew = r->K + (size_t)(s - 1) * n;
    const double a = (!last || s - 1 < m->n_b) ? row[s - 1] : 0.0;
    const double *next;
    int i, n_old;

    if (a != 0.0)
        for (i = 0; i < n; i++) r->P[i] = LEV_MADD(a, Knew[i], r->P[i]);
    if (last) {
        add_compensated(n, r->x, r->h, r->P, r->comp, r->xn, r->comp_new);
        r->err = m->err(n, normed(r->c->sys), r->K, r->h, r->x, r->xn, o->rtol, o->atol, o->atol_v);
        r->fac = 0.9 * pow(r->err, -m->expo);
        *dst = r->K + (size_t)m->f_slot * n;
        return r->xn;
    }
    for (i = 0; i < n; i++) r->tmp[i] = LEV_MADD(r->h, r->P[i], r->x[i]);
    /* the older part of the next combination: stage s + 1's row, or the solution's weights */
    next = s + 1 < m->stages ? m->A[s + 1] : m->B;
    n_old = s + 1 < m->stages ? s : (s < m->n_b ? s : m->n_b);
    rk_sum_n(n, NULL, 0.0, r->K, next, n_old, r->P);
    *dst = r->K + (size_t)s * n;
    return r->tmp;
}

/* Stage s of one run: its argument (adaptive_stage_arg), then the rhs into its slot of K. */
LEV_FORCE_INLINE void adaptive_stage(adaptive_run *r, int s, const adaptive_method *m, const int n)
{
    double *dst;
    const double *arg = adaptive_stage_arg(r, s, m, n, &dst);
    call_rhs(r->c, arg, dst);
}

/* After the stages: the error estimate, then a rejection (a smaller step, LEV_RUNNING) or the
 * step accepted: the energy monitor, the box event (located on the dense output by bisection),
 * the samples.  LEV_RUNNING or the run's final status. */
static int adaptive_judge(adaptive_run *r)
{
    lev_ctx *c = r->c;
    const lev_options *o = c->opt;
    const adaptive_method *m = r->m;
    lev_stats *st = c->st;
    int n = c->sys->n, dense_ready = 0, it;
    double *x = r->x, *swap, h = r->h, t_old, err, fac, e;

    err = r->err;
    if (!isfinite(err) || !all_finite(r->xn, n) || !all_finite(r->K + (size_t)m->f_slot * n, n)) {
        r->h_abs *= 0.2;
        st->rejected++;
        r->rejected_here = r->last_nonfinite = 1;
        return LEV_RUNNING;
    }
    r->last_nonfinite = 0;
    fac = r->fac;
    if (!(err < 1.0)) {
        r->h_abs *= fmax(0.2, fac);
        st->rejected++;
        r->rejected_here = 1;
        return LEV_RUNNING;
    }
    {
        double factor = (err == 0.0) ? 10.0 : fmin(10.0, fac);
        if (r->rejected_here) factor = fmin(1.0, factor);
        r->h_abs *= factor;
    }
    /* accept */
    r->rejected_here = 0;
    memcpy(r->yo, x, (size_t)n * sizeof(double));
    t_old = r->t;
    memcpy(x, r->xn, (size_t)n * sizeof(double));
    memcpy(r->f, r->K + (size_t)m->f_slot * n, (size_t)n * sizeof(double));
    swap = r->comp;
    r->comp = r->comp_new;
    r->comp_new = swap;
    r->t = r->t_new;
    st->steps++;
    st->h_last = h;
    st->t_final = r->t;
    if (r->h_abs > r->hmax) r->h_abs = r->hmax;
    e = monitor(c, x);

    if (o->box_on && box_outside(o, x)) {
        double lo = 0.0, hi = 1.0;
        m->prepare(c, r->yo, x, r->f, h, r->K, r->F, r->tmp);
        dense_ready = 1;
        for (it = 0; it < 80 && (hi - lo) * h > 2.0 * DBL_EPSILON * fabs(r->t); it++) {
            double mid = 0.5 * (lo + hi);
            m->eval(c, mid, h, r->yo, r->F, r->yd, r->K, r->tmp);
            if (all_finite(r->yd, n) && !box_outside(o, r->yd)) lo = mid; else hi = mid;
        }
        if (hi < 1.0) {
            m->eval(c, hi, h, r->yo, r->F, r->yd, r->K, r->tmp);
            if (all_finite(r->yd, n) && box_outside(o, r->yd)) {
                memcpy(x, r->yd, (size_t)n * sizeof(double));
                r->t = t_old + hi * h;
                st->t_final = r->t;
                e = c->sys->energy ? call_energy(c, x) : 0.0;
            }
        }
        while (o->t_out && r->i_out < o->n_out && o->t_out[r->i_out] < r->t) {
            double th = (o->t_out[r->i_out] - t_old) / h;
            m->eval(c, th, h, r->yo, r->F, r->yd, r->K, r->tmp);
            record(c, o->t_out[r->i_out], r->yd, c->sys->energy ? call_energy(c, r->yd) : 0.0);
            r->i_out++;
        }
        record(c, r->t, x, e);
        return LEV_LEFT_BOX;
    }
    if (energy_exceeded(c)) return LEV_ENERGY_LIMIT;
    if (o->t_out) {
        while (r->i_out < o->n_out && o->t_out[r->i_out] <= r->t) {
            if (o->t_out[r->i_out] == r->t) {
                record(c, r->t, x, e);
            } else {
                double th = (o->t_out[r->i_out] - t_old) / h;
                if (!dense_ready) {
                    m->prepare(c, r->yo, x, r->f, h, r->K, r->F, r->tmp);
                    dense_ready = 1;
                }
                m->eval(c, th, h, r->yo, r->F, r->yd, r->K, r->tmp);
                record(c, o->t_out[r->i_out], r->yd, c->sys->energy ? call_energy(c, r->yd) : 0.0);
            }
            r->i_out++;
        }
    } else if (o->every > 0 && st->steps % o->every == 0) {
        record(c, r->t, x, e);
    }
    return r->t < o->t_end ? LEV_RUNNING : LEV_COMPLETED;
}

/* All stages of an attempt.  Inlined with the method and n constant, and the stage loop unrolled,
 * the tableau's entries become constants in the code: the zero entries vanish, and no loop or
 * branch is left between the rhs calls (about 10% of a step of the full model). */
LEV_FORCE_INLINE void stages_of(adaptive_run *r, const adaptive_method *m, const int n)
{
    int s;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 17
#endif
    for (s = 1; s <= m->stages; s++) adaptive_stage(r, s, m, n);
}

/* The specialised copies: the two methods for the full (12) and reduced (4) models. */
static void attempt_stages(adaptive_run *r)
{
    const int n = r->c->sys->n;
    if (r->m == &DOP853_M && n == 12) stages_of(r, &DOP853_M, 12);
    else if (r->m == &VERN9_M && n == 12) stages_of(r, &VERN9_M, 12);
    else if (r->m == &DOP853_M && n == 4) stages_of(r, &DOP853_M, 4);
    else if (r->m == &VERN9_M && n == 4) stages_of(r, &VERN9_M, 4);
    else stages_of(r, r->m, n);
}

static int run_adaptive(lev_ctx *c, double *x, double *w, const adaptive_method *m)
{
    adaptive_run r;
    int status = adaptive_start(&r, c, x, w, m);
    while (status == LEV_RUNNING && (status = adaptive_next(&r)) == LEV_RUNNING) {
        attempt_stages(&r);
        status = adaptive_judge(&r);
    }
    return status;
}
