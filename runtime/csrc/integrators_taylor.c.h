/* Taylor's method over the generated coefficients (LEV_TAYLOR).
 * Part of integrators.c's translation unit: included there once, nowhere else. */
#ifndef LEV_INTEGRATORS_TU
#error "integrators_taylor.c.h is part of integrators.c: include it only there"
#endif

/* ---- Taylor's method over the generated coefficients (LEV_TAYLOR) ---- */

int lev_taylor_order(double rtol)
{
    const double p = ceil(-log(rtol) / 2.0 + 1.0);
    if (!(p >= 2.0)) return 2;                      /* also a NaN */
    return p > LEV_TAYLOR_MAX_ORDER ? LEV_TAYLOR_MAX_ORDER : (int)p;
}

/* inc_k = sum_{j=1..p} C_k^[j] h^j (Horner): the change of state k over h from the expansion point. */
static void taylor_increment(int n, int p, const double *C, double h, double *inc)
{
    int k, j;
    for (k = 0; k < n; k++) {
        const double *ck = C + (size_t)k * (size_t)(p + 1);
        double s = ck[p];
        for (j = p - 1; j >= 1; j--) s = LEV_MADD(s, h, ck[j]);
        inc[k] = s * h;
    }
}

/* The state at the expansion point + dt (the step's polynomial: dense output, the box event). */
static void taylor_dense(int n, int p, const double *C, double dt, double *y)
{
    int k;
    taylor_increment(n, p, C, dt, y);
    for (k = 0; k < n; k++) y[k] += C[(size_t)k * (size_t)(p + 1)];
}

/* The step from the coefficients (Jorba & Zou, Experiment. Math. 14, 2005, sec. 3): with the
 * component weights w_k = atol_k / rtol + |x_k| and N_j = max_k |C_k^[j]| / w_k, the radius of
 * convergence is estimated from the last two orders as rho = min(N_{p-1}^(-1/(p-1)), N_p^(-1/p)),
 * so that |C_k^[j]| <~ w_k rho^-j. A step h then errs in component k by about its first omitted
 * term, w_k (h / rho)^(p+1), and h = rho (s rtol)^(1/(p+1)) holds that to s rtol w_k per step, the
 * contract of every adaptive method here (s = LEV_TAYLOR_SAFETY; the order p = ceil(-ln rtol / 2
 * + 1) is Jorba & Zou's). Their own step, rho e^-2 e^(-0.7/(p-1)) (heyoka's), errs by about
 * (h / rho)^(p+1) <= rtol e^-4 e^-0.7 w_k < 0.01 rtol w_k per step: ten times or more below the
 * contract, in more and shorter steps (the bench's reduced runs at tol 1e-8: square 11 -> 8 steps,
 * ring_magnet 8 -> 6, loop 12 -> 8, reduced_only 21 -> 15; errors 2.5e-10 to 1.4e-9 of the scales).
 * `shrink` is (s rtol)^(1/(p+1)), computed once per run; rho comes from one exp of the larger of
 * ln(N_{p-1}) / (p-1) and ln(N_p) / p (the coefficients are finite here: run_taylor checks them
 * first, so the maxima need no NaN rule). */
#define LEV_TAYLOR_SAFETY 0.1
static double taylor_step(int n, int p, const double *C, const double *x, const lev_options *o,
                          double shrink)
{
    double n1 = 0.0, n2 = 0.0, l = -INFINITY;
    int k;
    for (k = 0; k < n; k++) {
        const double *ck = C + (size_t)k * (size_t)(p + 1);
        const double iw = 1.0 / ((o->atol_v ? o->atol_v[k] : o->atol) / o->rtol + fabs(x[k]));
        const double a = fabs(ck[p - 1]) * iw, b = fabs(ck[p]) * iw;
        if (a > n1) n1 = a;
        if (b > n2) n2 = b;
    }
    if (n1 > 0.0) l = log(n1) / (p - 1);
    if (n2 > 0.0 && log(n2) / p > l) l = log(n2) / p;
    return l == -INFINITY ? INFINITY : exp(-l) * shrink;
}

/* After an accepted step from t_old (coefficients C at the old state) to t: the box event located
 * on the step's polynomial by bisection, then the samples; LEV_RUNNING or the final status. */
static int taylor_after_step(lev_ctx *c, int p, const double *C, double t_old, double *t, double h,
                             double *x, double *yd, long *i_out, double e)
{
    const lev_options *o = c->opt;
    lev_stats *st = c->st;
    const int n = c->sys->n;
    int it;
    if (o->box_on && box_outside(o, x)) {
        double lo = 0.0, hi = 1.0;
        for (it = 0; it < 80 && (hi - lo) * h > 2.0 * DBL_EPSILON * fabs(*t); it++) {
            double mid = 0.5 * (lo + hi);
            taylor_dense(n, p, C, mid * h, yd);
            if (all_finite(yd, n) && !box_outside(o, yd)) lo = mid; else hi = mid;
        }
        if (hi < 1.0) {
            taylor_dense(n, p, C, hi * h, yd);
            if (all_finite(yd, n) && box_outside(o, yd)) {
                memcpy(x, yd, (size_t)n * sizeof(double));
                *t = t_old + hi * h;
                st->t_final = *t;
                e = c->sys->energy ? call_energy(c, x) : 0.0;
            }
        }
        while (o->t_out && *i_out < o->n_out && o->t_out[*i_out] < *t) {
            taylor_dense(n, p, C, o->t_out[*i_out] - t_old, yd);
            record(c, o->t_out[*i_out], yd, c->sys->energy ? call_energy(c, yd) : 0.0);
            (*i_out)++;
        }
        record(c, *t, x, e);
        return LEV_LEFT_BOX;
    }
    if (energy_exceeded(c)) return LEV_ENERGY_LIMIT;
    if (o->t_out) {
        while (*i_out < o->n_out && o->t_out[*i_out] <= *t) {
            if (o->t_out[*i_out] == *t) {
                record(c, *t, x, e);
            } else {
                taylor_dense(n, p, C, o->t_out[*i_out] - t_old, yd);
                record(c, o->t_out[*i_out], yd, c->sys->energy ? call_energy(c, yd) : 0.0);
            }
            (*i_out)++;
        }
    } else if (o->every > 0 && st->steps % o->every == 0) {
        record(c, *t, x, e);
    }
    return *t < o->t_end ? LEV_RUNNING : LEV_COMPLETED;
}

/* Taylor's method: at each step the coefficients of order p at x (sys->taylor), the step of
 * taylor_step, the new state by Horner and compensated summation. Every step is accepted (the
 * step is chosen from the coefficients so that the truncation error is about s rtol w_k); one
 * expansion per step (counted in st->iterations), no rhs call. */
static int run_taylor(lev_ctx *c, double *x, double *w)
{
    const lev_options *o = c->opt;
    lev_stats *st = c->st;
    const int n = c->sys->n, p = lev_taylor_order(o->rtol);
    double *C = w, *xn = C + (size_t)n * (size_t)(p + 1), *comp = xn + n, *comp_new = comp + n,
           *yd = comp_new + n, *swap;
    const double hmax = o->h_max > 0.0 ? o->h_max : o->t_end - o->t0;
    const double shrink = pow(LEV_TAYLOR_SAFETY * o->rtol, 1.0 / (p + 1)),
                 stretch = pow(LEV_TAYLOR_SAFETY, -1.0 / (p + 1));
    double t = o->t0;
    long i_out = 0;
    int k, status;
    for (k = 0; k < n; k++) comp[k] = 0.0;
    while (o->t_out && i_out < o->n_out && o->t_out[i_out] <= t) {
        record(c, t, x, st->energy0);
        i_out++;
    }
    for (;;) {
        double h, t_new, t_old, e;
        if (st->steps >= o->max_steps) return LEV_STEP_BUDGET;
        if (c->sys->taylor(x, c->sys->p, p, C) != 0) return LEV_BAD_INPUT;
        st->iterations++;
        if (!all_finite(C, n * (p + 1))) return LEV_NONFINITE;
        h = fmin(taylor_step(n, p, C, x, o, shrink), hmax);
        /* the last step may go without the safety factor (to rtol w_k rather than s rtol w_k) rather
         * than leave a sliver that costs one more expansion (as DOP853 stretches its last step by 1 %) */
        if (o->t_end - t <= h * stretch && o->t_end - t <= hmax) h = o->t_end - t;
        t_new = t + h < o->t_end ? t + h : o->t_end;
        h = t_new - t;
        if (!(h > 0.0) || h < 10.0 * (nextafter(t, INFINITY) - t))
            return LEV_STEP_UNDERFLOW;
        taylor_increment(n, p, C, h, yd);
        add_compensated(n, x, 1.0, yd, comp, xn, comp_new);
        if (!all_finite(xn, n)) return LEV_NONFINITE;
        memcpy(x, xn, (size_t)n * sizeof(double));
        swap = comp;
        comp = comp_new;
        comp_new = swap;
        t_old = t;
        t = t_new;
        st->steps++;
        st->h_last = h;
        st->t_final = t;
        e = monitor(c, x);
        status = taylor_after_step(c, p, C, t_old, &t, h, x, yd, &i_out, e);
        if (status != LEV_RUNNING) return status;
    }
}
