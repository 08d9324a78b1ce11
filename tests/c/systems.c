/* The test systems of the C integrators' tests (tests/c/test_integrators.py and others), with the
 * generated-model signature (runtime/csrc/integrators.h); compiled with runtime/csrc into the tests'
 * library only (tests/helpers/c_systems.py), never into a model's library or the wheel.
 *
 * lev_oscillator_*  the isotropic harmonic oscillator a = -w2 r, p[0] = w2 (a Hamiltonian system
 *                   whose circular orbits coincide with the circle test's, runtime/csrc/circle.c):
 *                   energy, Jacobian and Taylor coefficients (for LEV_TAYLOR: x^[n+1] = v^[n] / (n+1),
 *                   v^[n+1] = -w2 x^[n] / (n+1)).
 * lev_kepler_*      the Kepler problem a = -GM r / |r|^3, p[0] = GM: energy and Jacobian.
 * lev_blowup_rhs    x' = x^2 (one state): x(t) = x0 / (1 - x0 t) blows up in finite time.
 * lev_drift_rhs     x' = p[0] (one state): an angle at a constant rate, like the top's spin angle;
 *                   every method is exact on it, so what remains is the rounding of x + increment
 *                   (the test of the compensated summation).
 */
#include <math.h>

#include "integrators.h"

void lev_oscillator_rhs(const double *in, const double *p, double *out)
{
    out[0] = in[2];
    out[1] = in[3];
    out[2] = -p[0] * in[0];
    out[3] = -p[0] * in[1];
}

void lev_oscillator_energy(const double *in, const double *p, double *out)
{
    out[0] = 0.5 * (in[2] * in[2] + in[3] * in[3]) + 0.5 * p[0] * (in[0] * in[0] + in[1] * in[1]);
}

int lev_oscillator_taylor(const double *in, const double *p, int order, double *out)
{
    int k, n;
    const int m = order + 1;
    if (order < 1 || order > LEV_TAYLOR_MAX_ORDER) return -1;
    for (k = 0; k < 4; k++) out[k * m] = in[k];
    for (n = 0; n < order; n++)
        for (k = 0; k < 2; k++) {
            out[k * m + n + 1] = out[(k + 2) * m + n] / (n + 1);
            out[(k + 2) * m + n + 1] = -p[0] * out[k * m + n] / (n + 1);
        }
    return 0;
}

void lev_oscillator_jac(const double *in, const double *p, double *out)
{
    int i;
    (void)in;
    for (i = 0; i < 16; i++) out[i] = 0.0;
    out[0 * 4 + 2] = 1.0;
    out[1 * 4 + 3] = 1.0;
    out[2 * 4 + 0] = -p[0];
    out[3 * 4 + 1] = -p[0];
}

void lev_kepler_rhs(const double *in, const double *p, double *out)
{
    double r2 = in[0] * in[0] + in[1] * in[1];
    double r3 = r2 * sqrt(r2);
    out[0] = in[2];
    out[1] = in[3];
    out[2] = -p[0] * in[0] / r3;
    out[3] = -p[0] * in[1] / r3;
}

void lev_kepler_energy(const double *in, const double *p, double *out)
{
    double r = sqrt(in[0] * in[0] + in[1] * in[1]);
    out[0] = 0.5 * (in[2] * in[2] + in[3] * in[3]) - p[0] / r;
}

void lev_kepler_jac(const double *in, const double *p, double *out)
{
    double x = in[0], y = in[1], r2 = x * x + y * y, r = sqrt(r2), r3 = r2 * r, r5 = r3 * r2;
    int i;
    for (i = 0; i < 16; i++) out[i] = 0.0;
    out[0 * 4 + 2] = 1.0;
    out[1 * 4 + 3] = 1.0;
    out[2 * 4 + 0] = -p[0] * (1.0 / r3 - 3.0 * x * x / r5);
    out[2 * 4 + 1] = p[0] * 3.0 * x * y / r5;
    out[3 * 4 + 0] = p[0] * 3.0 * x * y / r5;
    out[3 * 4 + 1] = -p[0] * (1.0 / r3 - 3.0 * y * y / r5);
}

void lev_blowup_rhs(const double *in, const double *p, double *out)
{
    (void)p;
    out[0] = in[0] * in[0];
}

void lev_drift_rhs(const double *in, const double *p, double *out)
{
    (void)in;
    out[0] = p[0];
}
