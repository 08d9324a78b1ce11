/* several runs at once through a lane variant of the rhs (lev_integrate_lanes).
 * Part of integrators.c's translation unit: included there once, nowhere else. */
#ifndef LEV_INTEGRATORS_TU
#error "integrators_lanes.c.h is part of integrators.c: include it only there"
#endif

/* ---- several runs at once through a lane variant of the rhs (lev_integrate_lanes) ---- */

/* One lane: a run in progress with its own system, options, statistics and state. */
typedef struct {
    lev_system sys;
    lev_options opt;
    lev_stats st;
    lev_ctx c;
    adaptive_run r;
    double x[LEV_MAX_STATES];
    void *work;
    long k;                 /* the run in this lane */
    int active;
} lane;

typedef struct {
    int method;
    long count, next;
    lev_batch_setup setup;
    lev_batch_done done;
    void *user;
    const adaptive_method *m;
} lanes_state;

size_t lev_lanes_work_bytes(int method, int n)
{
    size_t one = lev_work_bytes(method, n);
    return one ? LEV_LANES * ((one + 63) / 64 * 64) : 0;
}

static void lane_finish(lanes_state *b, lane *l, int status)
{
    status = integrate_end(&l->c, l->x, status);
    b->done(b->user, l->k, status, &l->st, l->x);
    l->active = 0;
}

/* Start the next runs in lane l until one is under way (1) or none is left (0); a run that ends
 * at its start (bad options, outside the box, a nonfinite rhs) is reported at once. */
static int lane_open(lanes_state *b, lane *l)
{
    while (b->next < b->count) {
        int status;
        l->k = b->next++;
        memset(&l->sys, 0, sizeof l->sys);
        memset(&l->opt, 0, sizeof l->opt);
        if (b->setup(b->user, l->k, &l->sys, &l->opt, l->x) != 0 || l->sys.n > LEV_MAX_STATES
            || l->sys.quad) {
            memset(&l->st, 0, sizeof l->st);
            l->st.status = LEV_BAD_INPUT;
            b->done(b->user, l->k, LEV_BAD_INPUT, &l->st, l->x);
            continue;
        }
        status = integrate_begin(b->method, &l->sys, &l->opt, l->x, l->work, NULL, NULL, NULL,
                                 &l->st, &l->c);
        if (status != LEV_RUNNING) {
            b->done(b->user, l->k, status, &l->st, l->x);
            continue;
        }
        l->active = 1;
        status = adaptive_start(&l->r, &l->c, l->x, (double *)l->work, b->m);
        if (status != LEV_RUNNING) {
            lane_finish(b, l, status);
            continue;
        }
        return 1;
    }
    return 0;
}

/* The stages of one attempt of the ready lanes: each stage's arguments gathered into a structure
 * of arrays, one call of rhs_lanes, the results scattered into each run's K (a free lane repeats
 * the first ready one). Inlined with the method and n constant, as attempt_stages. */
LEV_FORCE_INLINE void lanes_stages(lane *lanes, const int *ready, int n_ready, lev_fn rhs_lanes,
                                   const adaptive_method *m, const int n, int n_p, double *in,
                                   double *pp, double *out)
{
    const double *arg[LEV_LANES];
    double *dst[LEV_LANES];
    int s, q, k;
    for (q = 0; q < LEV_LANES; q++) {
        const double *p = lanes[ready[q < n_ready ? q : 0]].sys.p;
        for (k = 0; k < n_p; k++) pp[k * LEV_LANES + q] = p[k];
    }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 17
#endif
    for (s = 1; s <= m->stages; s++) {
        for (q = 0; q < n_ready; q++) arg[q] = adaptive_stage_arg(&lanes[ready[q]].r, s, m, n, &dst[q]);
        for (k = 0; k < n; k++)
            for (q = 0; q < LEV_LANES; q++) in[k * LEV_LANES + q] = arg[q < n_ready ? q : 0][k];
        rhs_lanes(in, pp, out);
        for (q = 0; q < n_ready; q++) {
            for (k = 0; k < n; k++) dst[q][k] = out[k * LEV_LANES + q];
            lanes[ready[q]].st.rhs_evals++;
        }
    }
}

long lev_integrate_lanes(int method, int n, int n_p, lev_fn rhs_lanes, long count,
                         lev_batch_setup setup, lev_batch_done done, void *user, void *work)
{
    lane lanes[LEV_LANES];
    lanes_state b;
    double in[LEV_LANES * LEV_MAX_STATES], out[LEV_LANES * LEV_MAX_STATES];
    double pp[LEV_LANES * LEV_MAX_STATES];
    int ready[LEV_LANES], n_ready, q, status;
    size_t stride;

    if ((method != LEV_DOP853 && method != LEV_VERN9) || n <= 0 || n > LEV_MAX_STATES || n_p < 0
        || n_p > LEV_MAX_STATES || !rhs_lanes || count < 0 || !setup || !done || !work)
        return -1;
    b.method = method;
    b.count = count;
    b.next = 0;
    b.setup = setup;
    b.done = done;
    b.user = user;
    b.m = method == LEV_DOP853 ? &DOP853_M : &VERN9_M;
    stride = (lev_work_bytes(method, n) + 63) / 64 * 64;
    for (q = 0; q < LEV_LANES; q++) {
        lanes[q].work = (char *)work + (size_t)q * stride;
        lanes[q].active = 0;
        lane_open(&b, &lanes[q]);
    }
    for (;;) {
        n_ready = 0;
        for (q = 0; q < LEV_LANES; q++) {
            lane *l = &lanes[q];
            while (l->active) {
                status = adaptive_next(&l->r);
                if (status == LEV_RUNNING) {
                    ready[n_ready++] = q;
                    break;
                }
                lane_finish(&b, l, status);
                lane_open(&b, l);
            }
        }
        if (n_ready == 0) break;
        if (b.m == &DOP853_M && n == 12)
            lanes_stages(lanes, ready, n_ready, rhs_lanes, &DOP853_M, 12, n_p, in, pp, out);
        else if (b.m == &VERN9_M && n == 12)
            lanes_stages(lanes, ready, n_ready, rhs_lanes, &VERN9_M, 12, n_p, in, pp, out);
        else
            lanes_stages(lanes, ready, n_ready, rhs_lanes, b.m, n, n_p, in, pp, out);
        for (q = 0; q < n_ready; q++) {
            lane *l = &lanes[ready[q]];
            status = adaptive_judge(&l->r);
            if (status != LEV_RUNNING) {
                lane_finish(&b, l, status);
                lane_open(&b, l);
            }
        }
    }
    return count;
}
