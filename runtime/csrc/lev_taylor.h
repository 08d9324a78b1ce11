/* The Taylor recurrences of the generated models' Taylor functions (derive/emit/taylor.py writes the
 * tapes that call them); included by a model.c that has a Taylor function, after its LEV_FMA
 * (derive/emit/c/printer.py FMA_PRELUDE), through the include path runtime/model/load.py gives. */
#ifndef LEV_TAYLOR_H
#define LEV_TAYLOR_H

#ifndef LEV_FMA
#error "lev_taylor.h needs LEV_FMA: include it after the model's FMA prelude"
#endif

/* The recurrences of Taylor's method (derive/emit/taylor.py): degree n >= 1 of a node from the
 * degrees up to n of its operands and below n of itself. Each sum adds its terms of the degree-n
 * operands last: the rest depends only on lower degrees, so the processor computes it while the
 * degree-n values are still under way (the tape's nodes wait on each other only through those
 * last terms). r = 1 / n and the reciprocals of degree-0 values are passed in: no division. */
/* sum_{j=lo..hi} a[j] b[n - j] with b = b_n - j written as b[-j]: four chains in flight, chain k
 * summing the terms j = lo + k (mod 4), the leftover terms on chain 0. With AVX2 and hardware fma
 * the four chains are the four lanes of one vector: the same fused products added in the same
 * order, so the same bits as the scalar code (tests/derive/test_taylor.py builds both and compares). */
#if defined(FP_FAST_FMA) && defined(__AVX2__) && defined(__FMA__) && !defined(LEV_TAYLOR_SCALAR)
#include <immintrin.h>
static inline double lev_tay_old(const double *a, const double *b, int lo, int hi)
{
    __m256d s = _mm256_setzero_pd();
    double l[4];
    int j = lo;
    for (; j + 3 <= hi; j += 4)         /* b[-j-3 .. -j] reversed: lane k holds b[-j-k] */
        s = _mm256_fmadd_pd(_mm256_loadu_pd(a + j),
                            _mm256_permute4x64_pd(_mm256_loadu_pd(b - j - 3), 0x1B), s);
    _mm256_storeu_pd(l, s);
    for (; j <= hi; j++) l[0] = LEV_FMA(a[j], b[-j], l[0]);
    return (l[0] + l[1]) + (l[2] + l[3]);
}
#else
static inline double lev_tay_old(const double *a, const double *b, int lo, int hi)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int j = lo;
    for (; j + 3 <= hi; j += 4) {
        s0 = LEV_FMA(a[j], b[-j], s0);
        s1 = LEV_FMA(a[j + 1], b[-j - 1], s1);
        s2 = LEV_FMA(a[j + 2], b[-j - 2], s2);
        s3 = LEV_FMA(a[j + 3], b[-j - 3], s3);
    }
    for (; j <= hi; j++) s0 = LEV_FMA(a[j], b[-j], s0);
    return (s0 + s1) + (s2 + s3);
}
#endif

/* u = a b */
static inline double lev_tay_mul(const double *a, const double *b, int n)
{
    return LEV_FMA(a[n], b[0], LEV_FMA(a[0], b[n], lev_tay_old(a, b + n, 1, n - 1)));
}

/* u = a a: the products a[j] a[n-j] in pairs (half the work of lev_tay_mul) */
static inline double lev_tay_sqr(const double *a, int n)
{
    double s = 0.0;
    int j;
    for (j = 1; 2 * j < n; j++) s = LEV_FMA(a[j], a[n - j], s);
    s *= 2.0;
    if (n % 2 == 0) s = LEV_FMA(a[n / 2], a[n / 2], s);
    return LEV_FMA(2.0 * a[0], a[n], s);
}

/* u = 1 / a: u[n] = -u[0] sum_{j=1..n} a[j] u[n-j] */
static inline double lev_tay_inv(const double *a, const double *u, int n)
{
    return -u[0] * LEV_FMA(a[n], u[0], lev_tay_old(a, u + n, 1, n - 1));
}

/* u = sqrt(a): u[n] = (a[n] - sum_{j=1..n-1} u[j] u[n-j]) / (2 u[0]); h = 1 / (2 u[0]) */
static inline double lev_tay_sqrt(const double *a, const double *u, double h, int n)
{
    return (a[n] - lev_tay_old(u, u + n, 1, n - 1)) * h;
}

/* u = a^e: u[n] = sum_{j=0..n-1} (e (n-j) - j) a[n-j] u[j] / (n a[0]); ia = 1 / a[0] */
static inline double lev_tay_pow(const double *a, const double *u, double e, double ia, double r, int n)
{
    double s = 0.0;
    int j;
    for (j = 1; j < n; j++) s = LEV_FMA((e * (n - j) - j) * a[n - j], u[j], s);
    return LEV_FMA(e * n * a[n], u[0], s) * (ia * r);
}

/* u = exp(a): u[n] = sum_{j=1..n} j a[j] u[n-j] / n */
static inline double lev_tay_exp(const double *a, const double *u, double r, int n)
{
    double s = 0.0;
    int j;
    for (j = 1; j < n; j++) s = LEV_FMA(j * a[j], u[n - j], s);
    return LEV_FMA(n * a[n], u[0], s) * r;
}

/* u = log(a): u[n] = (a[n] - sum_{j=1..n-1} j u[j] a[n-j] / n) / a[0]; ia = 1 / a[0] */
static inline double lev_tay_log(const double *a, const double *u, double ia, double r, int n)
{
    double s = 0.0;
    int j;
    for (j = 1; j < n; j++) s = LEV_FMA(j * u[j], a[n - j], s);
    return (a[n] - s * r) * ia;
}

/* s = sin(a), c = cos(a): s[n] = sum_{j=1..n} j a[j] c[n-j] / n, c[n] = -sum j a[j] s[n-j] / n */
static inline double lev_tay_sin(const double *a, const double *c, double r, int n)
{
    double s = 0.0;
    int j;
    for (j = 1; j < n; j++) s = LEV_FMA(j * a[j], c[n - j], s);
    return LEV_FMA(n * a[n], c[0], s) * r;
}

static inline double lev_tay_cos(const double *a, const double *s_, double r, int n)
{
    double s = 0.0;
    int j;
    for (j = 1; j < n; j++) s = LEV_FMA(j * a[j], s_[n - j], s);
    return -LEV_FMA(n * a[n], s_[0], s) * r;
}

#endif
