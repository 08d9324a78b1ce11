/* the explicit slopes (Euler 3.1.2, RK4 3.1.3-3.1.4) and the Runge-Kutta stage sums, with compensated summation.
 * Part of integrators.c's translation unit: included there once, nowhere else. */
#ifndef LEV_INTEGRATORS_TU
#error "integrators_rk_stages.c.h is part of integrators.c: include it only there"
#endif

/* ---- fixed-step explicit methods: Euler (3.1.2), RK4 (3.1.3-3.1.4), DOP853 formula ---- */

/* The slope of an Euler step, x_{n+1} = x_n + h k (thesis eq. 3.1.2). */
static void euler_slope(lev_ctx *c, const double *x, double *k)
{
    call_rhs(c, x, k);
}

/* The slope of a classical Runge-Kutta step, x_{n+1} = x_n + h slope (thesis eq. 3.1.3). */
static void rk4_slope(lev_ctx *c, const double *x, double h, double *slope, double *w)
{
    int i, n = c->sys->n;
    double *a = w, *b = w + n, *cc = w + 2 * n, *d = w + 3 * n, *tmp = w + 4 * n;
    /* thesis eq. 3.1.4 (slopes, without the factor h) */
    call_rhs(c, x, a);
    for (i = 0; i < n; i++) tmp[i] = x[i] + 0.5 * h * a[i];
    call_rhs(c, tmp, b);
    for (i = 0; i < n; i++) tmp[i] = x[i] + 0.5 * h * b[i];
    call_rhs(c, tmp, cc);
    for (i = 0; i < n; i++) tmp[i] = x[i] + h * cc[i];
    call_rhs(c, tmp, d);
    for (i = 0; i < n; i++)                                      /* thesis eq. 3.1.3 */
        slope[i] = (a[i] + 2.0 * b[i] + 2.0 * cc[i] + d[i]) / 6.0;
}

/* ---- explicit Runge-Kutta stages: the DOP853 formula and Verner 9(8) ---- */

#ifdef FP_FAST_FMA
#define LEV_MADD(a, b, c) fma(a, b, c)      /* C99: fma is a hardware instruction here */
#else
#define LEV_MADD(a, b, c) ((a) * (b) + (c))
#endif

/* Specialised copies for a constant n need the inlining forced: left to itself the compiler
 * clones on another argument and keeps a run-time n (perf showed a `rep stos` for the zeroing). */
#if defined(__GNUC__) || defined(__clang__)
#define LEV_FORCE_INLINE static inline __attribute__((always_inline))
#else
#define LEV_FORCE_INLINE static inline
#endif

/* max(|a|, |b|) without fmax's NaN handling, which costs a libm call here (a NaN is caught by
 * the error test anyway). */
#define LEV_MAXABS(a, b) (fabs(a) > fabs(b) ? fabs(a) : fabs(b))

/* out = x + h sum_{j < s} a_j K_j over the nonzero a_j (x == NULL: the sum alone).  Inlined with
 * a constant n for the two model sizes (12: full, 4: reduced), and summed in a local array that
 * cannot alias K, so that the sums stay in vector registers: with a run-time n and the sum in
 * `out` the combinations cost a third of a DOP853 step (measured with perf). */
LEV_FORCE_INLINE void rk_sum_n(int n, const double *x, double h, const double *K, const double *a,
                            int s, double *out)
{
    double acc[LEV_MAX_STATES];
    int i, j;
    for (i = 0; i < n; i++) acc[i] = 0.0;
    for (j = 0; j < s; j++) {
        const double aj = a[j];
        const double *Kj = K + (size_t)j * n;
        if (aj == 0.0) continue;
        for (i = 0; i < n; i++) acc[i] = LEV_MADD(aj, Kj[i], acc[i]);
    }
    if (x)
        for (i = 0; i < n; i++) out[i] = LEV_MADD(h, acc[i], x[i]);
    else
        for (i = 0; i < n; i++) out[i] = acc[i];
}

static void rk_sum_or_combine(int n, const double *x, double h, const double *K, const double *a,
                              int s, double *out)
{
    if (n == 12) rk_sum_n(12, x, h, K, a, s, out);
    else if (n == 4) rk_sum_n(4, x, h, K, a, s, out);
    else rk_sum_n(n, x, h, K, a, s, out);
}

/* acc = sum_{j < s} a_j K_j. */
static void rk_sum(int n, const double *K, const double *a, int s, double *acc)
{
    rk_sum_or_combine(n, NULL, 0.0, K, a, s, acc);
}

/* out = x + h sum_{j < s} a_j K_j: the argument of a stage. */
static void rk_combine(int n, const double *x, double h, const double *K, const double *a, int s,
                       double *out)
{
    rk_sum_or_combine(n, x, h, K, a, s, out);
}

/* xn = x + h acc by compensated summation (Kahan; Hairer, Lubich & Wanner, Geometric Numerical
 * Integration, VIII.5): comp holds what earlier updates lost to rounding and comp_new receives
 * what this one loses (acc may be comp_new).  A step's increment is tiny against a state that
 * grows (the spin angle reaches hundreds of radians), and without it the rounding of
 * x + increment random-walks into the result: about 2e-13 of the bench's error measure. */
static void add_compensated(int n, const double *x, double h, const double *acc, const double *comp,
                            double *xn, double *comp_new)
{
    int i;
    for (i = 0; i < n; i++) {
        const double inc = LEV_MADD(h, acc[i], comp[i]);
        xn[i] = x[i] + inc;
        comp_new[i] = (x[i] - xn[i]) + inc;
    }
}

/* An explicit embedded pair with dense output, run by the adaptive driver (run_adaptive). */
typedef struct {
    int stages;             /* stages k_1 .. k_stages of a step; k_1 = rhs(x) (FSAL) */
    const double (*A)[16];  /* A[s][j], j < s: the argument of stage s */
    const double *B;        /* the solution's weights over the first n_b stages */
    int n_b;
    int f_slot;             /* the slot of K that holds rhs(xn) after a step */
    double expo;            /* the step-size exponent, 1 / (order of the estimate + 1) */
    double (*err)(int, int, const double *, double, const double *, const double *, double,
                  double, const double *);
    void (*prepare)(lev_ctx *, const double *, const double *, const double *, double, double *,
                    double *, double *);
    void (*eval)(lev_ctx *, double, double, const double *, const double *, double *, double *,
                 double *);
} adaptive_method;
