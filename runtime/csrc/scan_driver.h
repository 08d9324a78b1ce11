/* A chunk of a stability map in one call (runtime/scan/chunk_c.py; thesis 3.1-3.2, fig. 3.8).
 *
 * Every point of the chunk is one lev_integrate run (integrators.h) of the same system from its
 * own initial state, with its own parameter vector, tolerances, box and step budget, and with no
 * output samples and no energy monitor: a map needs only whether and when each run leaves the
 * box. A run stops at the first exit from the box (the integrators' box event), so a point that
 * falls costs only the steps until it falls. There is no Python per point. Given the model's lane
 * variant of the rhs (rhs_lanes, may be NULL), the adaptive methods run LEV_LANES points at once
 * through it (lev_integrate_lanes: the same numbers, point for point).
 *
 * Thread safety: no global mutable state; `work` (lev_scan_work_bytes(method, n) bytes, 16-byte aligned)
 * and all outputs belong to the caller, so chunks may run concurrently on different buffers.
 */
#ifndef LEVITRON_SCAN_DRIVER_H
#define LEVITRON_SCAN_DRIVER_H

#include "integrators.h"

/* Integrate n_points runs of d state/dt = rhs(state, p_k) from t = 0 to t_end.
 *
 *   method, rhs, jac    as lev_integrate (jac may be NULL)
 *   rhs_lanes           the lane variant of rhs (integrators.h), or NULL
 *   n, n_p              state dimension (at most LEV_MAX_STATES) and parameters per point
 *   t_end, rtol         shared by all points (rtol: adaptive methods only)
 *   ix, iy, iz          indices of x, y, z in the state (-1 if absent)
 *   max_iter            implicit methods: iteration limit per step (0 = default)
 *   x0[k n .. k n + n)  initial state of point k
 *   p[k n_p ..)         parameters of point k
 *   atol[k n ..)        adaptive methods: absolute tolerances of point k (may be NULL for fixed)
 *   h[k]                fixed-step methods: the step; adaptive: the first step (0 = automatic)
 *   box[3 k ..)         z_lo, z_hi, r_max of point k (r_max = inf: no radial limit)
 *   max_steps[k]        the step budget of point k (> 0; runtime/integrate/budget.py)
 * Outputs per point: status[k] (enum lev_status), t_final[k] (the time of the last state: t_end,
 * or the located exit from the box), rhs_evals[k], steps[k] (accepted steps) and, when x_final is
 * not NULL, x_final[k n ..) (the final state).
 * Returns the number of points run (n_points), or -1 for invalid arguments (nothing run). */
/* Bytes of `work` that lev_scan_chunk needs for this method and dimension. */
size_t lev_scan_work_bytes(int method, int n);

long lev_scan_chunk(int method, lev_fn rhs, lev_fn rhs_lanes, lev_fn jac, int n, int n_p,
                    double t_end, double rtol, int ix, int iy, int iz, int max_iter,
                    long n_points, const double *x0, const double *p, const double *atol,
                    const double *h, const double *box, const long *max_steps, void *work,
                    int *status, double *t_final, long *rhs_evals, long *steps, double *x_final);

#endif
