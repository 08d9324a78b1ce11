/* Dormand-Prince 8(5,3) and Verner 9(8): stages, error norms, dense output.
 * Part of integrators.c's translation unit: included there once, nowhere else. */
#ifndef LEV_INTEGRATORS_TU
#error "integrators_dop853_vern9.c.h is part of integrators.c: include it only there"
#endif

/* ---- Dormand-Prince 8(5,3), adaptive, with dense output ---- */

/* Hairer's error norm: err5 and err3 combined, RMS over the components (scipy's DOP853).  The
 * weighted sums run over the stages with a nonzero weight, vectorised over the components.  K's
 * stages have n components; the norm takes the first m (m = n - 1 leaves out a quadrature,
 * lev_system.quad, which does not steer the steps, as CVODES' quadratures do not by default). */
LEV_FORCE_INLINE double dp_error_norm_n(int n, int m, const double *K, double h, const double *x,
                                     const double *xn, double rtol, double atol,
                                     const double *atol_v)
{
    static const int NZ[9] = {0, 5, 6, 7, 8, 9, 10, 11, 12};   /* DP_E5, DP_E3 != 0 */
    double s5[LEV_MAX_STATES], s3[LEV_MAX_STATES], r[LEV_MAX_STATES], e5 = 0.0, e3 = 0.0, denom;
    int i, q;
    for (i = 0; i < m; i++) s5[i] = s3[i] = 0.0;
    for (q = 0; q < 9; q++) {
        const double *Kq = K + (size_t)NZ[q] * n, w5 = DP_E5[NZ[q]], w3 = DP_E3[NZ[q]];
        for (i = 0; i < m; i++) {
            s5[i] = LEV_MADD(w5, Kq[i], s5[i]);
            s3[i] = LEV_MADD(w3, Kq[i], s3[i]);
        }
    }
    if (atol_v)
        for (i = 0; i < m; i++) r[i] = 1.0 / (atol_v[i] + rtol * LEV_MAXABS(x[i], xn[i]));
    else
        for (i = 0; i < m; i++) r[i] = 1.0 / (atol + rtol * LEV_MAXABS(x[i], xn[i]));
    for (i = 0; i < m; i++) {
        const double a5 = s5[i] * r[i], a3 = s3[i] * r[i];
        e5 += a5 * a5;
        e3 += a3 * a3;
    }
    if (e5 == 0.0 && e3 == 0.0) return 0.0;
    denom = e5 + 0.01 * e3;
    return fabs(h) * e5 / sqrt(denom * (double)m);
}

static double dp_error_norm(int n, int m, const double *K, double h, const double *x,
                            const double *xn, double rtol, double atol, const double *atol_v)
{
    if (n == 12 && m == 12) return dp_error_norm_n(12, 12, K, h, x, xn, rtol, atol, atol_v);
    if (n == 4 && m == 4) return dp_error_norm_n(4, 4, K, h, x, xn, rtol, atol, atol_v);
    return dp_error_norm_n(n, m, K, h, x, xn, rtol, atol, atol_v);
}

/* The three extra stages and the coefficients F[0..6] of the 7th-degree interpolant. */
static void dp_dense_prepare(lev_ctx *c, const double *y_old, const double *y_new,
                             const double *f_new, double h, double *K, double *F, double *tmp)
{
    int s, j, i, r, n = c->sys->n;
    const double *f_old = K;
    for (s = 13; s < 16; s++) {
        rk_combine(n, y_old, h, K, DP_A[s], s, tmp);
        call_rhs(c, tmp, K + (size_t)s * n);
    }
    for (i = 0; i < n; i++) {
        double dy = y_new[i] - y_old[i];
        F[i] = dy;
        F[n + i] = h * f_old[i] - dy;
        F[2 * n + i] = 2.0 * dy - h * (f_new[i] + f_old[i]);
    }
    for (r = 0; r < 4; r++) {
        double *Fr = F + (size_t)(3 + r) * n;
        for (i = 0; i < n; i++) Fr[i] = 0.0;
        for (j = 0; j < 16; j++) {
            double d = DP_D[r][j];
            const double *Kj = K + (size_t)j * n;
            if (d == 0.0) continue;
            for (i = 0; i < n; i++) Fr[i] += d * Kj[i];
        }
        for (i = 0; i < n; i++) Fr[i] *= h;
    }
}

static void dp_dense_eval(int n, double theta, const double *y_old, const double *F, double *y)
{
    int i, r;
    for (i = 0; i < n; i++) y[i] = 0.0;
    for (r = 0; r < 7; r++) {
        const double *Fr = F + (size_t)(6 - r) * n;
        double m = (r % 2 == 0) ? theta : 1.0 - theta;
        for (i = 0; i < n; i++) y[i] = (y[i] + Fr[i]) * m;
    }
    for (i = 0; i < n; i++) y[i] += y_old[i];
}

static double rms_scaled(int n, const double *v, const double *x, double rtol, double atol,
                         const double *atol_v)
{
    int i;
    double s = 0.0;
    for (i = 0; i < n; i++) {
        double q = v[i] / ((atol_v ? atol_v[i] : atol) + rtol * fabs(x[i]));
        s += q * q;
    }
    return sqrt(s / (double)n);
}

/* Hairer's initial step (scipy select_initial_step, error estimator order 7). */
static double dp_initial_step(lev_ctx *c, const double *x, const double *f, double span,
                              double hmax, double *tmp, double *f1)
{
    int i, n = c->sys->n, m = normed(c->sys);
    double rtol = c->opt->rtol, atol = c->opt->atol, d0, d1, d2, h0, h1;
    d0 = rms_scaled(m, x, x, rtol, atol, c->opt->atol_v);
    d1 = rms_scaled(m, f, x, rtol, atol, c->opt->atol_v);
    h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (h0 > span) h0 = span;
    for (i = 0; i < n; i++) tmp[i] = x[i] + h0 * f[i];
    call_rhs(c, tmp, f1);
    for (i = 0; i < n; i++) tmp[i] = f1[i] - f[i];
    d2 = rms_scaled(m, tmp, x, rtol, atol, c->opt->atol_v) / h0;
    if (!isfinite(d2)) return h0;
    if (d1 <= 1e-15 && d2 <= 1e-15)
        h1 = fmax(1e-6, h0 * 1e-3);
    else
        h1 = pow(0.01 / fmax(d1, d2), 1.0 / 8.0);
    return fmin(fmin(100.0 * h0, h1), fmin(span, hmax));
}

static void dp_eval(lev_ctx *c, double theta, double h, const double *yo, const double *F,
                    double *y, double *K, double *tmp)
{
    (void)h; (void)K; (void)tmp;
    dp_dense_eval(c->sys->n, theta, yo, F, y);
}

/* Verner 9(8) without its estimate: stages k2..k15 from (x, f = k1) over h and the 9th-order
 * xn (the dense output; a step of the adaptive driver also computes k16 and rhs(xn)). */
static void vn_stages(lev_ctx *c, const double *x, const double *f, double h, double *K, double *xn,
                      double *tmp)
{
    int s, n = c->sys->n;
    memcpy(K, f, (size_t)n * sizeof(double));
    for (s = 1; s < 15; s++) {
        rk_combine(n, x, h, K, VN_A[s], s, tmp);
        call_rhs(c, tmp, K + (size_t)s * n);
    }
    rk_combine(n, x, h, K, VN_B, 15, xn);
}

/* RMS over the first m components of h sum_i VN_D_i k_i / (atol_k + rtol max(|x_k|, |xn_k|))
 * (dp_error_norm_n says which m). */
static double vn_error_norm(int n, int m, const double *K, double h, const double *x,
                            const double *xn, double rtol, double atol, const double *atol_v)
{
    double d[LEV_MAX_STATES], acc = 0.0;
    int i;
    rk_sum(n, K, VN_D, 16, d);
    for (i = 0; i < m; i++) {
        const double e = d[i] * (h / ((atol_v ? atol_v[i] : atol) + rtol * LEV_MAXABS(x[i], xn[i])));
        acc += e * e;
    }
    return sqrt(acc / (double)m);
}

/* Dense output of order 9: a Verner step of theta h from the start of the step (F = rhs(yo)). */
static void vn_prepare(lev_ctx *c, const double *y_old, const double *y_new, const double *f_new,
                       double h, double *K, double *F, double *tmp)
{
    (void)y_old; (void)y_new; (void)f_new; (void)h; (void)tmp;
    memcpy(F, K, (size_t)c->sys->n * sizeof(double));
}

static void vn_eval(lev_ctx *c, double theta, double h, const double *yo, const double *F,
                    double *y, double *K, double *tmp)
{
    vn_stages(c, yo, F, theta * h, K, y, tmp);
}

static const adaptive_method DOP853_M = {12, DP_A, DP_B, 12, 12, 1.0 / 8.0, dp_error_norm,
                                         dp_dense_prepare, dp_eval};
static const adaptive_method VERN9_M = {16, VN_A, VN_B, 15, 16, 1.0 / 9.0, vn_error_norm, vn_prepare,
                                        vn_eval};
