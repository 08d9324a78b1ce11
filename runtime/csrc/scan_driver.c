/* A chunk of a stability map in one call: see scan_driver.h (thesis 3.1-3.2, fig. 3.8). */
#include <stddef.h>
#include <string.h>

#include "scan_driver.h"

/* The chunk's arrays, read by chunk_setup and written by chunk_done. */
typedef struct {
    lev_fn rhs, jac;
    int n, n_p, fixed, ix, iy, iz, max_iter;
    double t_end, rtol;
    const double *x0, *p, *atol, *h, *box;
    const long *max_steps;
    int *status;
    double *t_final, *x_final;
    long *rhs_evals, *steps;
} chunk;

/* Point k: its own initial state, parameters, tolerances, box and step budget; no output samples
 * and no energy monitor (a map needs only whether and when each run leaves the box). */
static int chunk_setup(void *user, long k, lev_system *sys, lev_options *opt, double *x)
{
    const chunk *ch = (const chunk *)user;
    const size_t off = (size_t)k * (size_t)ch->n;
    memcpy(x, ch->x0 + off, (size_t)ch->n * sizeof(double));
    sys->n = ch->n;
    sys->rhs = ch->rhs;
    sys->jac = ch->jac;
    sys->energy = NULL;
    sys->p = ch->n_p > 0 ? ch->p + (size_t)k * (size_t)ch->n_p : NULL;
    opt->t0 = 0.0;
    opt->t_end = ch->t_end;
    opt->rtol = ch->fixed ? 0.0 : ch->rtol;
    opt->box_on = 1;
    opt->ix = ch->ix;
    opt->iy = ch->iy;
    opt->iz = ch->iz;
    opt->max_iter = ch->max_iter;
    opt->h = ch->h[k];
    opt->atol_v = ch->fixed ? NULL : ch->atol + off;
    opt->z_lo = ch->box[3 * k];
    opt->z_hi = ch->box[3 * k + 1];
    opt->r_max = ch->box[3 * k + 2];
    opt->max_steps = ch->max_steps[k];
    return 0;
}

static void chunk_done(void *user, long k, int status, const lev_stats *st, const double *x)
{
    chunk *ch = (chunk *)user;
    ch->status[k] = status;
    ch->t_final[k] = st->t_final;
    ch->rhs_evals[k] = st->rhs_evals;
    ch->steps[k] = st->steps;
    if (ch->x_final)
        memcpy(ch->x_final + (size_t)k * (size_t)ch->n, x, (size_t)ch->n * sizeof(double));
}

size_t lev_scan_work_bytes(int method, int n)
{
    size_t one = lev_work_bytes(method, n), lanes = lev_lanes_work_bytes(method, n);
    return one > lanes ? one : lanes;
}

long lev_scan_chunk(int method, lev_fn rhs, lev_fn rhs_lanes, lev_fn jac, int n, int n_p,
                    double t_end, double rtol, int ix, int iy, int iz, int max_iter,
                    long n_points, const double *x0, const double *p, const double *atol,
                    const double *h, const double *box, const long *max_steps, void *work,
                    int *status, double *t_final, long *rhs_evals, long *steps, double *x_final)
{
    chunk ch;
    lev_system sys;
    lev_options opt;
    lev_stats st;
    double xbuf[LEV_MAX_STATES];
    long k;
    int fixed = lev_method_fixed_step(method);

    if (fixed < 0 || !rhs || n <= 0 || n > LEV_MAX_STATES || n_p < 0 || n_points < 0 || !x0
        || (n_p > 0 && !p) || (!fixed && !atol) || !h || !box || !max_steps || !work || !status
        || !t_final || !rhs_evals || !steps)
        return -1;
    ch.rhs = rhs;
    ch.jac = jac;
    ch.n = n;
    ch.n_p = n_p;
    ch.fixed = fixed;
    ch.ix = ix;
    ch.iy = iy;
    ch.iz = iz;
    ch.max_iter = max_iter;
    ch.t_end = t_end;
    ch.rtol = rtol;
    ch.x0 = x0;
    ch.p = p;
    ch.atol = atol;
    ch.h = h;
    ch.box = box;
    ch.max_steps = max_steps;
    ch.status = status;
    ch.t_final = t_final;
    ch.x_final = x_final;
    ch.rhs_evals = rhs_evals;
    ch.steps = steps;
    if (rhs_lanes && (method == LEV_DOP853 || method == LEV_VERN9))
        return lev_integrate_lanes(method, n, n_p, rhs_lanes, n_points, chunk_setup, chunk_done,
                                   &ch, work);
    for (k = 0; k < n_points; k++) {         /* one run at a time: lev_integrate */
        memset(&sys, 0, sizeof sys);
        memset(&opt, 0, sizeof opt);
        chunk_setup(&ch, k, &sys, &opt, xbuf);
        lev_integrate(method, &sys, &opt, xbuf, work, NULL, NULL, NULL, &st);
        chunk_done(&ch, k, st.status, &st, xbuf);
    }
    return n_points;
}
