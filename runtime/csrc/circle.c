/* The thesis's solver test (3.1.3), with the generated-model signature (see integrators.h), which
 * `levitron bench` runs (runtime/bench/solver_compare.py): a mass point held on a circle by the
 * centripetal force F = -m v^2 / r (thesis eq. 3.1.8), directed to the centre: state (x, y, vx, vy),
 * a = -(|v|^2 / |r|^2) r.  On the exact solution |v| and |r| are constant; the energy checked is the
 * kinetic energy |v|^2 / 2 (per mass). The systems only the tests use are in tests/c/systems.c.
 */
#include <math.h>

#include "integrators.h"

void lev_circle_rhs(const double *in, const double *p, double *out)
{
    double r2 = in[0] * in[0] + in[1] * in[1];
    double v2 = in[2] * in[2] + in[3] * in[3];
    double k = v2 / r2;
    (void)p;
    out[0] = in[2];
    out[1] = in[3];
    out[2] = -k * in[0];
    out[3] = -k * in[1];
}

void lev_circle_energy(const double *in, const double *p, double *out)
{
    (void)p;
    out[0] = 0.5 * (in[2] * in[2] + in[3] * in[3]);
}
