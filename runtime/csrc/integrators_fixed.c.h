/* the fixed-step driver (Euler, RK4, the DOP853 formula).
 * Part of integrators.c's translation unit: included there once, nowhere else. */
#ifndef LEV_INTEGRATORS_TU
#error "integrators_fixed.c.h is part of integrators.c: include it only there"
#endif

/* The number of fixed steps over [t0, t_end] and the step h that makes them end at t_end (the
 * requested step rounded down so that an integer number fits). */
static long fixed_step_count(const lev_options *o, double *h)
{
    const double span = o->t_end - o->t0;
    long N = (long)ceil(span / o->h * (1.0 - 1e-12));
    if (N < 1) N = 1;
    *h = span / (double)N;
    return N;
}

/* Euler, RK4 and the DOP853 formula at a fixed step, the state updated by compensated summation
 * (add_compensated). */
static int run_fixed(int method, lev_ctx *c, double *x, double *w)
{
    const lev_options *o = c->opt;
    lev_stats *st = c->st;
    int i, n = c->sys->n, s;
    double h, e;
    double *xn = w, *comp = w + n, *comp_new = w + 2 * n, *slope = w + 3 * n, *scratch = w + 4 * n;
    double *swap;
    long N, k;

    N = fixed_step_count(o, &h);
    st->h_last = h;
    for (i = 0; i < n; i++) comp[i] = 0.0;
    for (k = 1; k <= N; k++) {
        if (st->steps >= o->max_steps) return LEV_STEP_BUDGET;
        if (method == LEV_EULER) {
            euler_slope(c, x, slope);
        } else if (method == LEV_RK4) {
            rk4_slope(c, x, h, slope, scratch);
        } else {                                     /* the DOP853 formula: stages k_1 .. k_12 */
            double *K = scratch, *tmp = scratch + 12 * n;
            call_rhs(c, x, K);
            for (s = 1; s < 12; s++) {
                rk_combine(n, x, h, K, DP_A[s], s, tmp);
                call_rhs(c, tmp, K + (size_t)s * n);
            }
            rk_sum(n, K, DP_B, 12, slope);
        }
        add_compensated(n, x, h, slope, comp, xn, comp_new);
        if (!all_finite(xn, n)) return LEV_NONFINITE;   /* x keeps the last finite state */
        memcpy(x, xn, (size_t)n * sizeof(double));
        swap = comp;
        comp = comp_new;
        comp_new = swap;
        st->steps++;
        st->t_final = (k == N) ? o->t_end : o->t0 + (double)k * h;
        e = monitor(c, x);
        if (outside(o, x)) {
            record(c, st->t_final, x, e);
            return LEV_LEFT_BOX;
        }
        if (energy_exceeded(c)) return LEV_ENERGY_LIMIT;
        if (o->every > 0 && k % o->every == 0) record(c, st->t_final, x, e);
    }
    return LEV_COMPLETED;
}
