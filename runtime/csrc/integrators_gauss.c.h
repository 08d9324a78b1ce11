/* Gauss-Legendre collocation (implicit midpoint, order 4), symplectic.
 * Part of integrators.c's translation unit: included there once, nowhere else. */
#ifndef LEV_INTEGRATORS_TU
#error "integrators_gauss.c.h is part of integrators.c: include it only there"
#endif

/* ---- Gauss-Legendre collocation (s = 1: implicit midpoint; s = 2: order 4), symplectic ---- */

/* LU with partial pivoting, in place; returns 0 if singular. */
static int lu_factor(double *M, int *piv, int N)
{
    int i, j, k;
    for (k = 0; k < N; k++) {
        int p = k;
        double best = fabs(M[(size_t)k * N + k]);
        for (i = k + 1; i < N; i++) {
            double v = fabs(M[(size_t)i * N + k]);
            if (v > best) { best = v; p = i; }
        }
        piv[k] = p;
        if (best == 0.0 || !isfinite(best)) return 0;
        if (p != k) {
            for (j = 0; j < N; j++) {
                double t = M[(size_t)k * N + j];
                M[(size_t)k * N + j] = M[(size_t)p * N + j];
                M[(size_t)p * N + j] = t;
            }
        }
        for (i = k + 1; i < N; i++) {
            double l = M[(size_t)i * N + k] / M[(size_t)k * N + k];
            M[(size_t)i * N + k] = l;
            if (l == 0.0) continue;
            for (j = k + 1; j < N; j++) M[(size_t)i * N + j] -= l * M[(size_t)k * N + j];
        }
    }
    return 1;
}

static void lu_solve(const double *M, const int *piv, int N, double *b)
{
    int i, j;
    for (i = 0; i < N; i++) {
        double t = b[piv[i]];
        b[piv[i]] = b[i];
        b[i] = t;
    }
    for (i = 1; i < N; i++) {
        double s = b[i];
        for (j = 0; j < i; j++) s -= M[(size_t)i * N + j] * b[j];
        b[i] = s;
    }
    for (i = N - 1; i >= 0; i--) {
        double s = b[i];
        for (j = i + 1; j < N; j++) s -= M[(size_t)i * N + j] * b[j];
        b[i] = s / M[(size_t)i * N + i];
    }
}

/* One Gauss-Legendre run's state: the tableau, the stage values Z (s n, relative to x), the
 * simplified Newton matrix and the work arrays (run_gauss's layout of w). */
typedef struct {
    lev_ctx *c;
    const lev_options *o;
    lev_stats *st;
    int n, s, m, maxit, use_newton, last_iters;
    double A[2][2], cc[2], d[2], W[2][2];
    double h;
    double *Z, *Zp, *F, *dZ, *G, *Y, *comp, *xn, *J, *M;
    int *piv;
} gauss_run;

/* The s-stage Gauss tableau (s = 1: the implicit midpoint rule), d = b^T A^{-1}, and the
 * extrapolation of the collocation polynomial through (0, 0), (c_j, Z_j) to the next step's
 * nodes: W[i][j] = L_j(1 + c_i) - L_j(1). */
static void gauss_tableau(gauss_run *g)
{
    int s = g->s, i, j, q;
    double r3 = sqrt(3.0);
    if (s == 1) {
        g->A[0][0] = 0.5; g->cc[0] = 0.5; g->d[0] = 2.0;
    } else {
        g->A[0][0] = 0.25; g->A[0][1] = 0.25 - r3 / 6.0;
        g->A[1][0] = 0.25 + r3 / 6.0; g->A[1][1] = 0.25;
        g->cc[0] = 0.5 - r3 / 6.0; g->cc[1] = 0.5 + r3 / 6.0;
        g->d[0] = -r3; g->d[1] = r3;
    }
    for (i = 0; i < s; i++) {
        for (j = 0; j < s; j++) {
            double tau1 = 1.0 + g->cc[i], l1 = tau1 / g->cc[j], l0 = 1.0 / g->cc[j];
            for (q = 0; q < s; q++) {
                if (q == j) continue;
                l1 *= (tau1 - g->cc[q]) / (g->cc[j] - g->cc[q]);
                l0 *= (1.0 - g->cc[q]) / (g->cc[j] - g->cc[q]);
            }
            g->W[i][j] = l1 - l0;
        }
    }
}

/* The starting stage values of a step: c_i h f(x) on the first, else the previous step's
 * collocation polynomial extrapolated (W). */
static void gauss_predict(gauss_run *g, const double *x, long step)
{
    int s = g->s, n = g->n, i, j, k;
    if (step == 1) {
        call_rhs(g->c, x, g->Y);
        for (i = 0; i < s; i++)
            for (k = 0; k < n; k++) g->Z[i * n + k] = g->cc[i] * g->h * g->Y[k];
        return;
    }
    memcpy(g->Zp, g->Z, (size_t)g->m * sizeof(double));
    for (i = 0; i < s; i++)
        for (k = 0; k < n; k++) {
            double v = 0.0;
            for (j = 0; j < s; j++) v += g->W[i][j] * g->Zp[j * n + k];
            g->Z[i * n + k] = v;
        }
}

/* With a quadrature (lev_system.quad) jac wrote the (n - 1) x (n - 1) Jacobian of rhs row-major at
 * the start of J: spread it to n x n with W's row and column zero (dW/dt depends on the state, but
 * simplified Newton needs no exact matrix: W's stage equations are explicit in the others', and
 * the iteration converges to the same stages). */
static void quad_jacobian(double *J, int n)
{
    int m = n - 1, k, q;
    for (k = m - 1; k >= 0; k--)          /* backwards: a target index is never below its source */
        for (q = m - 1; q >= 0; q--)
            J[(size_t)k * n + q] = J[(size_t)k * m + q];
    for (k = 0; k < m; k++) J[(size_t)k * n + m] = 0.0;
    for (q = 0; q < n; q++) J[(size_t)m * n + q] = 0.0;
}

/* Simplified Newton: M = I - h (A (x) J(x)), factored; a singular M falls back to fixed-point
 * iteration for the rest of the run. LEV_RUNNING, or LEV_NONFINITE for a non-finite Jacobian. */
static int gauss_newton_matrix(gauss_run *g, const double *x)
{
    int s = g->s, n = g->n, m = g->m, i, j, k, q;
    g->c->sys->jac(x, g->c->sys->p, g->J);
    g->st->jac_evals++;
    if (g->c->sys->quad) quad_jacobian(g->J, n);
    for (i = 0; i < s; i++)
        for (j = 0; j < s; j++)
            for (k = 0; k < n; k++)
                for (q = 0; q < n; q++)
                    g->M[(size_t)(i * n + k) * m + (size_t)(j * n + q)] =
                        (i == j && k == q ? 1.0 : 0.0) - g->h * g->A[i][j] * g->J[(size_t)k * n + q];
    if (!lu_factor(g->M, g->piv, m)) {
        if (!all_finite(g->J, n * n)) return LEV_NONFINITE;
        g->use_newton = 0;
        g->maxit = g->o->max_iter > 0 ? g->o->max_iter : 200;
    }
    return LEV_RUNNING;
}

/* One iteration on the stage equations G(Z) = Z - h (A (x) I) F(x + Z) = 0; *delta: the largest
 * increment relative to the state's scale. LEV_RUNNING or LEV_NONFINITE. */
static int gauss_iterate(gauss_run *g, const double *x, double *delta)
{
    int s = g->s, n = g->n, m = g->m, i, j, k, l;
    for (i = 0; i < s; i++) {
        for (k = 0; k < n; k++) g->Y[k] = x[k] + g->Z[i * n + k];
        call_rhs(g->c, g->Y, g->F + i * n);
    }
    for (i = 0; i < s; i++)
        for (k = 0; k < n; k++) {
            double v = g->Z[i * n + k];
            for (j = 0; j < s; j++) v -= g->h * g->A[i][j] * g->F[j * n + k];
            g->G[i * n + k] = v;
        }
    if (!all_finite(g->G, m)) return LEV_NONFINITE;
    for (i = 0; i < m; i++) g->dZ[i] = -g->G[i];
    if (g->use_newton) lu_solve(g->M, g->piv, m, g->dZ);
    *delta = 0.0;
    for (i = 0; i < s; i++)
        for (k = 0; k < n; k++) {
            double sc = fabs(x[k]), q;
            for (l = 0; l < s; l++) sc = fmax(sc, fabs(g->Z[l * n + k]));
            g->Z[i * n + k] += g->dZ[i * n + k];
            if (g->dZ[i * n + k] == 0.0) continue;
            q = fabs(g->dZ[i * n + k]) / (sc > 0.0 ? sc : DBL_MIN);
            if (q > *delta) *delta = q;
        }
    g->st->iterations++;
    return LEV_RUNNING;
}

/* The stage equations of a step solved to round-off: an increment below a quarter ulp of the
 * state, or increments that stop decreasing once tiny (Hairer, McLachlan & Razakarivony 2008).
 * LEV_RUNNING, LEV_NONFINITE or LEV_NO_CONVERGENCE. */
static int gauss_solve_stages(gauss_run *g, const double *x)
{
    double delta = INFINITY, delta_prev = INFINITY;
    int converged = 0, it, status;
    for (it = 0; it < g->maxit; it++) {
        if ((status = gauss_iterate(g, x, &delta)) != LEV_RUNNING) return status;
        if (delta <= 0.25 * DBL_EPSILON || (it >= 1 && delta >= delta_prev && delta_prev < 1e-10)) {
            converged = 1;
            break;
        }
        delta_prev = delta;
    }
    g->last_iters = it + 1;
    if (!converged && !(delta < 1e-12)) return LEV_NO_CONVERGENCE;
    return LEV_RUNNING;
}

/* x_{n+1} = x_n + sum_j d_j Z_j (d = b^T A^{-1}) with compensated summation, then the step's
 * bookkeeping, box, energy monitor and samples. LEV_RUNNING or the status that ends the run. */
static int gauss_advance(gauss_run *g, double *x, long step, long N)
{
    const lev_options *o = g->o;
    int n = g->n, s = g->s, j, k;
    double e;
    for (k = 0; k < n; k++) {
        double inc = g->comp[k];
        for (j = 0; j < s; j++) inc += g->d[j] * g->Z[j * n + k];
        g->xn[k] = x[k] + inc;
        g->comp[k] = (x[k] - g->xn[k]) + inc;
    }
    if (!all_finite(g->xn, n)) return LEV_NONFINITE;
    memcpy(x, g->xn, (size_t)n * sizeof(double));
    g->st->steps++;
    g->st->t_final = (step == N) ? o->t_end : o->t0 + (double)step * g->h;
    e = monitor(g->c, x);
    if (outside(o, x)) {
        record(g->c, g->st->t_final, x, e);
        return LEV_LEFT_BOX;
    }
    if (energy_exceeded(g->c)) return LEV_ENERGY_LIMIT;
    if (o->every > 0 && step % o->every == 0) record(g->c, g->st->t_final, x, e);
    return LEV_RUNNING;
}

static int run_gauss(int method, lev_ctx *c, double *x, double *w)
{
    gauss_run g;
    long N, step;
    int k, status;

    g.c = c;
    g.o = c->opt;
    g.st = c->st;
    g.n = c->sys->n;
    g.s = (int)gauss_stages(method);
    g.m = g.s * g.n;
    g.Z = w;
    g.Zp = g.Z + g.m;
    g.F = g.Zp + g.m;
    g.dZ = g.F + g.m;
    g.G = g.dZ + g.m;
    g.Y = g.G + g.m;
    g.comp = g.Y + g.n;
    g.xn = g.comp + g.n;
    g.J = g.xn + g.n;
    g.M = g.J + (size_t)g.n * g.n;
    g.piv = (int *)(g.M + (size_t)g.m * g.m);
    g.use_newton = c->sys->jac != NULL;
    g.last_iters = 0;
    gauss_tableau(&g);
    g.maxit = g.o->max_iter > 0 ? g.o->max_iter : (g.use_newton ? 30 : 200);

    N = fixed_step_count(g.o, &g.h);
    g.st->h_last = g.h;
    for (k = 0; k < g.n; k++) g.comp[k] = 0.0;

    for (step = 1; step <= N; step++) {
        if (g.st->steps >= g.o->max_steps) return LEV_STEP_BUDGET;
        gauss_predict(&g, x, step);
        /* M refactored only when the previous step needed more than 4 iterations (a stale J
           slows convergence, never its limit) */
        if (g.use_newton && (step == 1 || g.last_iters > 4)
            && (status = gauss_newton_matrix(&g, x)) != LEV_RUNNING)
            return status;
        if ((status = gauss_solve_stages(&g, x)) != LEV_RUNNING) return status;
        if ((status = gauss_advance(&g, x, step, N)) != LEV_RUNNING) return status;
    }
    return LEV_COMPLETED;
}
