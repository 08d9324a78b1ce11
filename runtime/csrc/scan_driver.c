/* A chunk of a stability map in one call: see scan_driver.h (thesis 3.1-3.2, fig. 3.8). */
#include <stddef.h>
#include <string.h>

#include "scan_driver.h"

long lev_scan_chunk(int method, lev_fn rhs, lev_fn jac, int n, int n_p, double t_end, double rtol,
                    int ix, int iy, int iz, int max_iter, long n_points,
                    const double *x0, const double *p, const double *atol, const double *h,
                    const double *box, const long *max_steps, void *work,
                    int *status, double *t_final, long *rhs_evals, long *steps, double *x_final)
{
    lev_system sys;
    lev_options opt;
    lev_stats st;
    double xbuf[LEV_MAX_STATES];
    long k;
    int fixed = lev_method_fixed_step(method);

    if (fixed < 0 || !rhs || n <= 0 || n > LEV_MAX_STATES || n_p < 0 || n_points < 0 || !x0 || (n_p > 0 && !p)
        || (!fixed && !atol) || !h || !box || !max_steps || !work || !status || !t_final
        || !rhs_evals || !steps)
        return -1;

    memset(&sys, 0, sizeof sys);
    sys.n = n;
    sys.rhs = rhs;
    sys.jac = jac;
    sys.energy = NULL;                 /* no energy monitor: a map needs only the box */

    memset(&opt, 0, sizeof opt);
    opt.t0 = 0.0;
    opt.t_end = t_end;
    opt.rtol = fixed ? 0.0 : rtol;
    opt.box_on = 1;
    opt.ix = ix;
    opt.iy = iy;
    opt.iz = iz;
    opt.max_iter = max_iter;
    opt.t_out = NULL;                  /* no dense-output samples ... */
    opt.every = 0;                     /* ... and no step samples */
    opt.max_samples = 0;

    for (k = 0; k < n_points; k++) {
        const size_t off = (size_t)k * (size_t)n;
        memcpy(xbuf, x0 + off, (size_t)n * sizeof(double));
        sys.p = n_p > 0 ? p + (size_t)k * (size_t)n_p : NULL;
        opt.h = h[k];
        opt.atol_v = fixed ? NULL : atol + off;
        opt.z_lo = box[3 * k];
        opt.z_hi = box[3 * k + 1];
        opt.r_max = box[3 * k + 2];
        opt.max_steps = max_steps[k];
        status[k] = lev_integrate(method, &sys, &opt, xbuf, work, NULL, NULL, NULL, &st);
        t_final[k] = st.t_final;
        rhs_evals[k] = st.rhs_evals;
        steps[k] = st.steps;
        if (x_final) memcpy(x_final + off, xbuf, (size_t)n * sizeof(double));
    }
    return n_points;
}
