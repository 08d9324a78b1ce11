/* sin x and cos x inline for the generated models (their printer calls lev_sincos and, in the lane
 * variants, lev_sincos_lanes: derive/emit/c/printer.py); included by a model.c that needs them
 * (derive/emit/c/templates/model.c.j2), found through the include path runtime/model/load.py
 * gives, and in the library's cache key with every header of runtime/csrc. */
#ifndef LEV_SINCOS_H
#define LEV_SINCOS_H

#include <math.h>

/* The core of sin x and cos x (inline, no call on the hot path): x reduced by q pi/2 (Cody-Waite,
 * two parts), then fdlibm's kernel polynomials on [-pi/4, pi/4]: sr = sin r, cr = cos r, x = q pi/2
 * + r; within 1 ulp (absolute error <= 1.2e-16) for |x| < 1e5. */
static inline void lev_sincos_kernel(double x, double *q, double *sr, double *cr)
{
    static const double PIO2_1 = 1.57079632673412561417e+00, PIO2_1T = 6.07710050650619224932e-11;
    static const double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
        S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
        S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
    static const double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
        C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
        C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
    double r, z, hz, w;
    *q = nearbyint(x * 0.63661977236758134308);
    r = (x - *q * PIO2_1) - *q * PIO2_1T;
    z = r * r;
    *sr = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    hz = 0.5 * z;
    w = 1.0 - hz;
    *cr = w + (((1.0 - w) - hz) + z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6))))));
}

/* sin x and cos x together: the kernel and its quadrant, libm beyond |x| < 1e5. */
static inline void lev_sincos(double x, double *s, double *c)
{
    double q, sr, cr;
    if (!(fabs(x) < 1e5)) {
        *s = sin(x);
        *c = cos(x);
        return;
    }
    lev_sincos_kernel(x, &q, &sr, &cr);
    switch ((long)q & 3) {
    case 0: *s = sr; *c = cr; break;
    case 1: *s = cr; *c = -sr; break;
    case 2: *s = -sr; *c = -cr; break;
    default: *s = -cr; *c = sr; break;
    }
}

/* lev_sincos without its branches, for the lane variants (the lanes loop vectorises): the same
 * kernel, the quadrant's swap and signs as exact products by 0 and +-1, so the same numbers;
 * valid for |x| < 1e5 (the lane variants check and fall back). */
static inline void lev_sincos_lanes(double x, double *s, double *c)
{
    double q, sr, cr, q4, hi, odd;
    lev_sincos_kernel(x, &q, &sr, &cr);
    q4 = q - 4.0 * nearbyint(0.25 * q - 0.375);          /* q mod 4, exactly */
    hi = nearbyint(0.5 * q4 - 0.25);                       /* 1 for q4 = 2, 3 */
    odd = q4 - 2.0 * hi;                                   /* 1 for q4 = 1, 3 */
    *s = (1.0 - 2.0 * hi) * (sr * (1.0 - odd) + cr * odd);
    *c = (1.0 - 2.0 * (hi + odd - 2.0 * hi * odd)) * (cr * (1.0 - odd) + sr * odd);
}

#endif
