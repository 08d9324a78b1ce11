/* Generic ODE integrators over the generated model functions; see integrators.h.
 *
 * Euler (thesis 3.1.2) and classical Runge-Kutta 4 (thesis 3.1.3-3.1.4) at a fixed step;
 * Dormand-Prince 8(5,3) with the step-size control, error norm and 7th-degree dense output of
 * Hairer's dop853 (coefficients as in scipy.integrate._ivp.dop853_coefficients, exact doubles);
 * Verner's "most efficient" 9(8) pair (Numer. Algor. 53, 2010) under the same driver
 * (run_adaptive), its dense output a Verner step of theta h (order 9, 15 evaluations per point);
 * s-stage Gauss-Legendre collocation (s = 1: implicit midpoint, s = 2: order 4), symplectic,
 * with the stage equations solved to round-off by simplified Newton (generated Jacobian) or by
 * fixed-point iteration, and compensated summation of the state update.
 *
 * No global mutable state: every buffer is provided by the caller.
 */
#define _POSIX_C_SOURCE 199309L
#include "integrators.h"

#include <float.h>
#include <math.h>
#include <string.h>
#include <time.h>

/* ---- Dormand-Prince 8(5,3) coefficients (Hairer, Norsett, Wanner I, II.10; scipy) ---- */
/* The systems are autonomous, so the nodes c_i are not needed. */
static const double DP_A[16][16] = {
    {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.05260015195876773, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.0197250569845379, 0.0591751709536137, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.02958758547680685, 0.0, 0.08876275643042054, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.03709200011850479, 0.0, 0.0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402, 0.008273789163814023, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.6241109587160757, 0.0, 0.0, -3.3608926294469414, -0.868219346841726, 27.59209969944671, 20.154067550477894, -43.48988418106996, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.47766253643826434, 0.0, 0.0, -2.4881146199716677, -0.590290826836843, 21.230051448181193, 15.279233632882423, -33.28821096898486, -0.020331201708508627, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {-0.9371424300859873, 0.0, 0.0, 5.186372428844064, 1.0914373489967295, -8.149787010746927, -18.52006565999696, 22.739487099350505, 2.4936055526796523, -3.0467644718982196, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {2.273310147516538, 0.0, 0.0, -10.53449546673725, -2.0008720582248625, -17.9589318631188, 27.94888452941996, -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, 0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259, 0.0, 0.0, 0.0, 0.0},
    {0.056167502283047954, 0.0, 0.0, 0.0, 0.0, 0.0, 0.25350021021662483, -0.2462390374708025, -0.12419142326381637, 0.15329179827876568, 0.00820105229563469, 0.007567897660545699, -0.008298, 0.0, 0.0, 0.0},
    {0.03183464816350214, 0.0, 0.0, 0.0, 0.0, 0.028300909672366776, 0.053541988307438566, -0.05492374857139099, 0.0, 0.0, -0.00010834732869724932, 0.0003825710908356584, -0.00034046500868740456, 0.1413124436746325, 0.0, 0.0},
    {-0.42889630158379194, 0.0, 0.0, 0.0, 0.0, -4.697621415361164, 7.683421196062599, 4.06898981839711, 0.3567271874552811, 0.0, 0.0, 0.0, -0.0013990241651590145, 2.9475147891527724, -9.15095847217987, 0.0},
};
static const double DP_B[12] = {
    0.054293734116568765, 0.0, 0.0, 0.0,
    0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585,
    0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259};
static const double DP_E3[13] = {
    -0.18980075407240762, 0.0, 0.0, 0.0,
    0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585,
    -0.4226823213237919, -0.1521609496625161, 0.20136540080403034, 0.02265179219836082,
    0.0};
static const double DP_E5[13] = {
    0.01312004499419488, 0.0, 0.0, 0.0,
    0.0, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864,
    -0.35032884874997366, 0.3341791187130175, 0.08192320648511571, -0.022355307863886294,
    0.0};
static const double DP_D[4][16] = {
    {-8.428938276109013, 0.0, 0.0, 0.0, 0.0, 0.5667149535193777, -3.0689499459498917, 2.38466765651207, 2.117034582445028, -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331, 18.148505520854727, -9.194632392478356, -4.436036387594894},
    {10.427508642579134, 0.0, 0.0, 0.0, 0.0, 242.28349177525817, 165.20045171727028, -374.5467547226902, -22.113666853125306, 7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845, -31.139403219565178, -9.35292435884448, 35.81684148639408},
    {19.985053242002433, 0.0, 0.0, 0.0, 0.0, -387.0373087493518, -189.17813819516758, 527.8081592054236, -11.57390253995963, 6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508, -60.19669523126412, 84.32040550667716, 11.99229113618279},
    {-25.69393346270375, 0.0, 0.0, 0.0, 0.0, -154.18974869023643, -231.5293791760455, 357.6391179106141, 93.40532418362432, -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114, 96.32455395918828, -39.17726167561544, -149.72683625798564},
};

/* ---- Verner's "most efficient" 9(8) pair (J. H. Verner, Numer. Algor. 53 (2010) 383-396) ----
 * 16 stages: the 9th-order solution uses k1, k8..k15; the 8th-order embedded one differs from it
 * by h sum VN_D_i k_i (k16 at c = 1 only serves the estimate). Coefficients as double values. */
static const double VN_A[16][16] = {
    {0},
    {0.03462},
    {-0.03893354388572875, 0.13595789452450918},
    {0.03638413148954267, 0.0, 0.10915239446862801},
    {2.0257639143939694, 0.0, -7.638023836496291, 6.173259922102322},
    {0.05112275589406061, 0.0, 0.0, 0.17708237945550218, 0.0008027762409222536},
    {0.13160063579752163, 0.0, 0.0, -0.2957276252669636, 0.08781378035642955, 0.6213052975225274},
    {0.07166666666666667, 0.0, 0.0, 0.0, 0.0, 0.33055335789153195, 0.2427799754418014},
    {0.071806640625, 0.0, 0.0, 0.0, 0.0, 0.3294380283228177, 0.1165190029271823, -0.034013671875},
    {0.04836757646340646, 0.0, 0.0, 0.0, 0.0, 0.03928989925676164, 0.10547409458903446,
     -0.021438652846483126, -0.10412291746271944},
    {-0.026645614872014785, 0.0, 0.0, 0.0, 0.0, 0.03333333333333333, -0.1631072244872467,
     0.03396081684127761, 0.1572319413814626, 0.21522674780318796},
    {0.03689009248708622, 0.0, 0.0, 0.0, 0.0, -0.1465181576725543, 0.2242577768172024,
     0.02294405717066073, -0.0035850052905728597, 0.08669223316444385, 0.43838406519683376},
    {-0.4866012215113341, 0.0, 0.0, 0.0, 0.0, -6.304602650282853, -0.2812456182894729,
     -2.679019236219849, 0.5188156639241577, 1.3653531876033418, 5.8850910885039465,
     2.8028087862720628},
    {0.4185367457753472, 0.0, 0.0, 0.0, 0.0, 6.724547581906459, -0.42544428016461133,
     3.3432791530012653, 0.6170816631175374, -0.9299661239399329, -6.099948804751011,
     -3.002206187889399, 0.2553202529443446},
    {-0.7793740861228848, 0.0, 0.0, 0.0, 0.0, -13.937342538107776, 1.2520488533793563,
     -14.691500408016868, -0.494705058533141, 2.2429749091462368, 13.367893803828643,
     14.396650486650687, -0.79758133317768, 0.4409353709534278},
    {2.0580513374668867, 0.0, 0.0, 0.0, 0.0, 22.357937727968032, 0.9094981099755646,
     35.89110098240264, -3.442515027624454, -4.865481358036369, -18.909803813543427,
     -34.26354448030452, 1.2647565216956427},
};
static const double VN_B[16] = {
    0.014611976858423152, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.3915211862331339,
    0.23109325002895065, 0.12747667699928525, 0.2246434176204158, 0.5684352689748513,
    0.058258715572158275, 0.13643174034822156, 0.030570139830827976, 0.0};
static const double VN_D[16] = {
    -0.005357988290444578, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -2.583020491182464,
    0.14252253154686625, 0.013420653512688676, -0.02867296291409493, 2.624999655215792,
    -0.2825509643291537, 0.13643174034822156, 0.030570139830827976, -0.04834231373823958};

/* ---- bookkeeping shared by all methods ---- */

typedef struct {
    const lev_system *sys;
    const lev_options *opt;
    lev_stats *st;
    double *out_t, *out_x, *out_e;
    double t_last_rec;  /* time of the last recorded sample (avoids duplicates) */
    int recorded_any;
} lev_ctx;

static void call_rhs(lev_ctx *c, const double *x, double *out)
{
    const lev_system *s = c->sys;
    s->rhs(x, s->p, out);
    if (s->quad) s->quad(x, s->p, out + s->n - 1);   /* dW/dt: the quadrature, the last state */
    c->st->rhs_evals++;
}

/* The components an adaptive step's error norm takes: all but a quadrature (lev_system.quad). */
static int normed(const lev_system *s)
{
    return s->quad ? s->n - 1 : s->n;
}

static double call_energy(lev_ctx *c, const double *x)
{
    double e = 0.0;
    c->sys->energy(x, c->sys->p, &e);
    c->st->energy_evals++;
    return e;
}

static int all_finite(const double *x, int n)
{
    int k;
    for (k = 0; k < n; k++)
        if (!isfinite(x[k])) return 0;
    return 1;
}

/* 1 iff the state is outside the box: z below z_lo or above z_hi, or sqrt(x^2 + y^2) > r_max
 * (compared squared: no hypot call on every step). */
static int box_outside(const lev_options *o, const double *x)
{
    if (o->iz >= 0 && (x[o->iz] > o->z_hi || x[o->iz] < o->z_lo)) return 1;
    if (isfinite(o->r_max) && (o->ix >= 0 || o->iy >= 0)) {
        const double a = o->ix >= 0 ? x[o->ix] : 0.0, b = o->iy >= 0 ? x[o->iy] : 0.0;
        return a * a + b * b > o->r_max * o->r_max;
    }
    return 0;
}

static int outside(const lev_options *o, const double *x)
{
    return o->box_on && box_outside(o, x);
}

static void record(lev_ctx *c, double t, const double *x, double e)
{
    int n = c->sys->n;
    lev_stats *st = c->st;
    if (c->recorded_any && t == c->t_last_rec) return;
    if (st->n_samples >= c->opt->max_samples || !c->out_x || !c->out_t) {
        st->dropped++;
        return;
    }
    c->out_t[st->n_samples] = t;
    memcpy(c->out_x + (size_t)st->n_samples * (size_t)n, x, (size_t)n * sizeof(double));
    if (c->out_e) c->out_e[st->n_samples] = e;
    st->n_samples++;
    c->t_last_rec = t;
    c->recorded_any = 1;
}

/* energy bookkeeping after an accepted step; returns the energy (0 if not monitored) */
static double monitor(lev_ctx *c, const double *x)
{
    double e, d;
    if (!c->sys->energy) return 0.0;
    e = call_energy(c, x);
    d = fabs(e - c->st->energy0);
    if (d > c->st->energy_max_dev || !isfinite(d)) c->st->energy_max_dev = d;
    return e;
}

static int energy_exceeded(const lev_ctx *c)
{
    return c->opt->energy_limit > 0.0 && c->sys->energy
        && !(c->st->energy_max_dev <= c->opt->energy_limit * fabs(c->st->energy0));
}

const char *lev_status_message(int status)
{
    switch (status) {
    case LEV_COMPLETED: return "completed: reached t_end";
    case LEV_LEFT_BOX: return "stopped: the state left the box";
    case LEV_NONFINITE: return "stopped: the right-hand side became non-finite (inf/nan)";
    case LEV_STEP_UNDERFLOW: return "stopped: the adaptive step size underflowed";
    case LEV_STEP_BUDGET: return "stopped: the step budget (max_steps) ran out before t_end";
    case LEV_NO_CONVERGENCE: return "stopped: the implicit stage equations did not converge";
    case LEV_BAD_INPUT: return "invalid input: check n, step, tolerances, buffers and t_out";
    case LEV_ENERGY_LIMIT: return "stopped: the energy drifted beyond the requested limit";
    default: return "unknown status";
    }
}

/* ---- the method table and the struct sizes (checked against runtime/integrate/methods.py) ---- */

static const char *const METHOD_NAMES[] = {"euler", "rk4", "dop853", "gauss4", "midpoint",
                                           "dop853-fixed", "vern9", "taylor"};
#define LEV_N_METHODS ((int)(sizeof METHOD_NAMES / sizeof METHOD_NAMES[0]))

int lev_method_id(const char *name)
{
    int k;
    if (!name) return -1;
    for (k = 0; k < LEV_N_METHODS; k++)
        if (strcmp(name, METHOD_NAMES[k]) == 0) return k;
    return -1;
}

const char *lev_method_name(int method)
{
    return (method >= 0 && method < LEV_N_METHODS) ? METHOD_NAMES[method] : NULL;
}

int lev_method_fixed_step(int method)
{
    if (method < 0 || method >= LEV_N_METHODS) return -1;
    return method != LEV_DOP853 && method != LEV_VERN9 && method != LEV_TAYLOR;
}

size_t lev_sizeof_system(void) { return sizeof(lev_system); }
size_t lev_sizeof_options(void) { return sizeof(lev_options); }
size_t lev_sizeof_stats(void) { return sizeof(lev_stats); }
size_t lev_sizeof_job(void) { return sizeof(lev_job); }

/* ---- work layout ---- */

/* Work of an adaptive run (adaptive_start): K (17 n), xn, f, tmp, F (7 n), yd, yo, f1, comp,
 * comp_new, P. */
#define ADAPTIVE_WORK 33

static size_t gauss_stages(int method) { return method == LEV_MIDPOINT ? 1u : 2u; }

void lev_rows(lev_fn f, long rows, int n_in, int n_out, const double *in, const double *p,
              double *out)
{
    for (long r = 0; r < rows; ++r)
        f(in + r * n_in, p, out + r * n_out);
}

size_t lev_work_bytes(int method, int n)
{
    size_t N = (size_t)(n > 0 ? n : 1), s, m;
    switch (method) {
    /* fixed steps: xn, comp, comp_new, slope, then the method's own (run_fixed) */
    case LEV_EULER: return 4 * N * sizeof(double);
    case LEV_RK4: return 9 * N * sizeof(double);
    case LEV_DOP853_FIXED: return 17 * N * sizeof(double);
    case LEV_DOP853:
    case LEV_VERN9: return ADAPTIVE_WORK * N * sizeof(double);
    /* the coefficients (LEV_TAYLOR_MAX_ORDER + 1 per state), xn, comp, comp_new, yd, inc */
    case LEV_TAYLOR: return ((size_t)(LEV_TAYLOR_MAX_ORDER + 1) * N + 5 * N) * sizeof(double);
    case LEV_GAUSS4:
    case LEV_MIDPOINT:
        s = gauss_stages(method);
        m = s * N;
        /* Z, Zprev, F, dZ, G (5 m), Y, comp, xnew (3 N), J (N^2), M (m^2); pivots (m ints) */
        return (5 * m + 3 * N + N * N + m * m) * sizeof(double) + m * sizeof(int) + 16;
    default: return 0;
    }
}

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

/* ---- Dormand-Prince 8(5,3), adaptive, with dense output ---- */

/* Hairer's error norm: err5 and err3 combined, RMS over the components (scipy's DOP853).  The
 * weighted sums run over the stages with a nonzero weight, vectorised over the components.  K's
 * stages have n components; the norm takes the first m (m = n - 1 leaves out a quadrature,
 * lev_system.quad, which does not steer the steps, as CVODES' quadratures do not by default). */
LEV_FORCE_INLINE double dp_error_norm_n(int n, int m, const double *K, double h, const double *x,
                                     const double *xn, double rtol, double atol,
                                     const double *atol_v)
{
    static const int NZ[9] = {0, 5, 6, 7, 8, 9, 10, 11, 12};   /* DP_E5, DP_E3 != 0 */
    double s5[LEV_MAX_STATES], s3[LEV_MAX_STATES], r[LEV_MAX_STATES], e5 = 0.0, e3 = 0.0, denom;
    int i, q;
    for (i = 0; i < m; i++) s5[i] = s3[i] = 0.0;
    for (q = 0; q < 9; q++) {
        const double *Kq = K + (size_t)NZ[q] * n, w5 = DP_E5[NZ[q]], w3 = DP_E3[NZ[q]];
        for (i = 0; i < m; i++) {
            s5[i] = LEV_MADD(w5, Kq[i], s5[i]);
            s3[i] = LEV_MADD(w3, Kq[i], s3[i]);
        }
    }
    if (atol_v)
        for (i = 0; i < m; i++) r[i] = 1.0 / (atol_v[i] + rtol * LEV_MAXABS(x[i], xn[i]));
    else
        for (i = 0; i < m; i++) r[i] = 1.0 / (atol + rtol * LEV_MAXABS(x[i], xn[i]));
    for (i = 0; i < m; i++) {
        const double a5 = s5[i] * r[i], a3 = s3[i] * r[i];
        e5 += a5 * a5;
        e3 += a3 * a3;
    }
    if (e5 == 0.0 && e3 == 0.0) return 0.0;
    denom = e5 + 0.01 * e3;
    return fabs(h) * e5 / sqrt(denom * (double)m);
}

static double dp_error_norm(int n, int m, const double *K, double h, const double *x,
                            const double *xn, double rtol, double atol, const double *atol_v)
{
    if (n == 12 && m == 12) return dp_error_norm_n(12, 12, K, h, x, xn, rtol, atol, atol_v);
    if (n == 4 && m == 4) return dp_error_norm_n(4, 4, K, h, x, xn, rtol, atol, atol_v);
    return dp_error_norm_n(n, m, K, h, x, xn, rtol, atol, atol_v);
}

/* The three extra stages and the coefficients F[0..6] of the 7th-degree interpolant. */
static void dp_dense_prepare(lev_ctx *c, const double *y_old, const double *y_new,
                             const double *f_new, double h, double *K, double *F, double *tmp)
{
    int s, j, i, r, n = c->sys->n;
    const double *f_old = K;
    for (s = 13; s < 16; s++) {
        rk_combine(n, y_old, h, K, DP_A[s], s, tmp);
        call_rhs(c, tmp, K + (size_t)s * n);
    }
    for (i = 0; i < n; i++) {
        double dy = y_new[i] - y_old[i];
        F[i] = dy;
        F[n + i] = h * f_old[i] - dy;
        F[2 * n + i] = 2.0 * dy - h * (f_new[i] + f_old[i]);
    }
    for (r = 0; r < 4; r++) {
        double *Fr = F + (size_t)(3 + r) * n;
        for (i = 0; i < n; i++) Fr[i] = 0.0;
        for (j = 0; j < 16; j++) {
            double d = DP_D[r][j];
            const double *Kj = K + (size_t)j * n;
            if (d == 0.0) continue;
            for (i = 0; i < n; i++) Fr[i] += d * Kj[i];
        }
        for (i = 0; i < n; i++) Fr[i] *= h;
    }
}

static void dp_dense_eval(int n, double theta, const double *y_old, const double *F, double *y)
{
    int i, r;
    for (i = 0; i < n; i++) y[i] = 0.0;
    for (r = 0; r < 7; r++) {
        const double *Fr = F + (size_t)(6 - r) * n;
        double m = (r % 2 == 0) ? theta : 1.0 - theta;
        for (i = 0; i < n; i++) y[i] = (y[i] + Fr[i]) * m;
    }
    for (i = 0; i < n; i++) y[i] += y_old[i];
}

static double rms_scaled(int n, const double *v, const double *x, double rtol, double atol,
                         const double *atol_v)
{
    int i;
    double s = 0.0;
    for (i = 0; i < n; i++) {
        double q = v[i] / ((atol_v ? atol_v[i] : atol) + rtol * fabs(x[i]));
        s += q * q;
    }
    return sqrt(s / (double)n);
}

/* Hairer's initial step (scipy select_initial_step, error estimator order 7). */
static double dp_initial_step(lev_ctx *c, const double *x, const double *f, double span,
                              double hmax, double *tmp, double *f1)
{
    int i, n = c->sys->n, m = normed(c->sys);
    double rtol = c->opt->rtol, atol = c->opt->atol, d0, d1, d2, h0, h1;
    d0 = rms_scaled(m, x, x, rtol, atol, c->opt->atol_v);
    d1 = rms_scaled(m, f, x, rtol, atol, c->opt->atol_v);
    h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (h0 > span) h0 = span;
    for (i = 0; i < n; i++) tmp[i] = x[i] + h0 * f[i];
    call_rhs(c, tmp, f1);
    for (i = 0; i < n; i++) tmp[i] = f1[i] - f[i];
    d2 = rms_scaled(m, tmp, x, rtol, atol, c->opt->atol_v) / h0;
    if (!isfinite(d2)) return h0;
    if (d1 <= 1e-15 && d2 <= 1e-15)
        h1 = fmax(1e-6, h0 * 1e-3);
    else
        h1 = pow(0.01 / fmax(d1, d2), 1.0 / 8.0);
    return fmin(fmin(100.0 * h0, h1), fmin(span, hmax));
}

static void dp_eval(lev_ctx *c, double theta, double h, const double *yo, const double *F,
                    double *y, double *K, double *tmp)
{
    (void)h; (void)K; (void)tmp;
    dp_dense_eval(c->sys->n, theta, yo, F, y);
}

/* Verner 9(8) without its estimate: stages k2..k15 from (x, f = k1) over h and the 9th-order
 * xn (the dense output; a step of the adaptive driver also computes k16 and rhs(xn)). */
static void vn_stages(lev_ctx *c, const double *x, const double *f, double h, double *K, double *xn,
                      double *tmp)
{
    int s, n = c->sys->n;
    memcpy(K, f, (size_t)n * sizeof(double));
    for (s = 1; s < 15; s++) {
        rk_combine(n, x, h, K, VN_A[s], s, tmp);
        call_rhs(c, tmp, K + (size_t)s * n);
    }
    rk_combine(n, x, h, K, VN_B, 15, xn);
}

/* RMS over the first m components of h sum_i VN_D_i k_i / (atol_k + rtol max(|x_k|, |xn_k|))
 * (dp_error_norm_n says which m). */
static double vn_error_norm(int n, int m, const double *K, double h, const double *x,
                            const double *xn, double rtol, double atol, const double *atol_v)
{
    double d[LEV_MAX_STATES], acc = 0.0;
    int i;
    rk_sum(n, K, VN_D, 16, d);
    for (i = 0; i < m; i++) {
        const double e = d[i] * (h / ((atol_v ? atol_v[i] : atol) + rtol * LEV_MAXABS(x[i], xn[i])));
        acc += e * e;
    }
    return sqrt(acc / (double)m);
}

/* Dense output of order 9: a Verner step of theta h from the start of the step (F = rhs(yo)). */
static void vn_prepare(lev_ctx *c, const double *y_old, const double *y_new, const double *f_new,
                       double h, double *K, double *F, double *tmp)
{
    (void)y_old; (void)y_new; (void)f_new; (void)h; (void)tmp;
    memcpy(F, K, (size_t)c->sys->n * sizeof(double));
}

static void vn_eval(lev_ctx *c, double theta, double h, const double *yo, const double *F,
                    double *y, double *K, double *tmp)
{
    vn_stages(c, yo, F, theta * h, K, y, tmp);
}

static const adaptive_method DOP853_M = {12, DP_A, DP_B, 12, 12, 1.0 / 8.0, dp_error_norm,
                                         dp_dense_prepare, dp_eval};
static const adaptive_method VERN9_M = {16, VN_A, VN_B, 15, 16, 1.0 / 9.0, vn_error_norm, vn_prepare,
                                        vn_eval};


/* The number of fixed steps over [t0, t_end] and the step h that makes them end at t_end (the
 * requested step rounded down so that an integer number fits). */
static long fixed_step_count(const lev_options *o, double *h)
{
    const double span = o->t_end - o->t0;
    long N = (long)ceil(span / o->h * (1.0 - 1e-12));
    if (N < 1) N = 1;
    *h = span / (double)N;
    return N;
}

/* Euler, RK4 and the DOP853 formula at a fixed step, the state updated by compensated summation
 * (add_compensated). */
static int run_fixed(int method, lev_ctx *c, double *x, double *w)
{
    const lev_options *o = c->opt;
    lev_stats *st = c->st;
    int i, n = c->sys->n, s;
    double h, e;
    double *xn = w, *comp = w + n, *comp_new = w + 2 * n, *slope = w + 3 * n, *scratch = w + 4 * n;
    double *swap;
    long N, k;

    N = fixed_step_count(o, &h);
    st->h_last = h;
    for (i = 0; i < n; i++) comp[i] = 0.0;
    for (k = 1; k <= N; k++) {
        if (st->steps >= o->max_steps) return LEV_STEP_BUDGET;
        if (method == LEV_EULER) {
            euler_slope(c, x, slope);
        } else if (method == LEV_RK4) {
            rk4_slope(c, x, h, slope, scratch);
        } else {                                     /* the DOP853 formula: stages k_1 .. k_12 */
            double *K = scratch, *tmp = scratch + 12 * n;
            call_rhs(c, x, K);
            for (s = 1; s < 12; s++) {
                rk_combine(n, x, h, K, DP_A[s], s, tmp);
                call_rhs(c, tmp, K + (size_t)s * n);
            }
            rk_sum(n, K, DP_B, 12, slope);
        }
        add_compensated(n, x, h, slope, comp, xn, comp_new);
        if (!all_finite(xn, n)) return LEV_NONFINITE;   /* x keeps the last finite state */
        memcpy(x, xn, (size_t)n * sizeof(double));
        swap = comp;
        comp = comp_new;
        comp_new = swap;
        st->steps++;
        st->t_final = (k == N) ? o->t_end : o->t0 + (double)k * h;
        e = monitor(c, x);
        if (outside(o, x)) {
            record(c, st->t_final, x, e);
            return LEV_LEFT_BOX;
        }
        if (energy_exceeded(c)) return LEV_ENERGY_LIMIT;
        if (o->every > 0 && k % o->every == 0) record(c, st->t_final, x, e);
    }
    return LEV_COMPLETED;
}

/* ---- the adaptive driver ---- */

/* One adaptive run between step attempts (run_adaptive: start, then per attempt next, the
 * stages, judge). */
typedef struct {
    lev_ctx *c;
    const adaptive_method *m;
    double *x;                       /* the state: the caller's buffer */
    double *K, *xn, *f, *tmp, *F, *yd, *yo, *f1, *comp, *comp_new, *P;
    double t, t_new, h, h_abs, hmax;
    double err, fac;                 /* the attempt's error estimate and step factor */
    long i_out;
    int rejected_here, last_nonfinite;
} adaptive_run;

#define LEV_RUNNING (-1)


/* The first evaluation, the first step size and the samples at t0; LEV_RUNNING or a status. */
static int adaptive_start(adaptive_run *r, lev_ctx *c, double *x, double *w,
                          const adaptive_method *m)
{
    const lev_options *o = c->opt;
    int i, n = c->sys->n;
    double span = o->t_end - o->t0;
    r->c = c;
    r->m = m;
    r->x = x;
    r->K = w;
    r->xn = w + 17 * n;
    r->f = w + 18 * n;
    r->tmp = w + 19 * n;
    r->F = w + 20 * n;
    r->yd = w + 27 * n;
    r->yo = w + 28 * n;
    r->f1 = w + 29 * n;
    r->comp = w + 30 * n;
    r->comp_new = w + 31 * n;
    r->P = w + 32 * n;
    r->t = o->t0;
    r->h = 0.0;
    r->i_out = 0;
    r->rejected_here = r->last_nonfinite = 0;
    for (i = 0; i < n; i++) r->comp[i] = 0.0;
    call_rhs(c, x, r->f);
    if (!all_finite(r->f, n)) return LEV_NONFINITE;
    r->hmax = o->h_max > 0.0 ? o->h_max : span;
    r->h_abs = o->h > 0.0 ? o->h : dp_initial_step(c, x, r->f, span, r->hmax, r->tmp, r->f1);
    if (r->h_abs > r->hmax) r->h_abs = r->hmax;
    while (o->t_out && r->i_out < o->n_out && o->t_out[r->i_out] <= r->t) {
        record(c, r->t, x, c->st->energy0);
        r->i_out++;
    }
    return LEV_RUNNING;
}

/* Before an attempt: the step size, the budget; K[0] = rhs(x).  LEV_RUNNING or a status. */
static int adaptive_next(adaptive_run *r)
{
    const lev_options *o = r->c->opt;
    lev_stats *st = r->c->st;
    double t_new;
    /* the step may not fall below 10 ulp of t (nextafter, a libm call, only when it could) */
    if (!(r->h_abs > 1e-13 * fabs(r->t) && r->h_abs > 1e-300)
        && r->h_abs < 10.0 * (nextafter(r->t, INFINITY) - r->t))
        return r->last_nonfinite ? LEV_NONFINITE : LEV_STEP_UNDERFLOW;
    if (st->steps + st->rejected >= o->max_steps) return LEV_STEP_BUDGET;
    t_new = r->t + r->h_abs;
    if (t_new > o->t_end) t_new = o->t_end;
    r->t_new = t_new;
    r->h = t_new - r->t;
    memcpy(r->K, r->f, (size_t)r->c->sys->n * sizeof(double));
    memset(r->P, 0, (size_t)r->c->sys->n * sizeof(double));    /* stage 1 has no older stage */
    return LEV_RUNNING;
}

/* Stage s (1 <= s < stages) of the attempt, or for s == stages the solution xn (compensated),
 * its error estimate and K[f_slot] = rhs(xn).
 *
 * Only the newest stage is on the critical path: the sum over the older stages (P) for the next
 * combination is formed before this stage's rhs is called, so that the processor computes it
 * while the rhs runs; the error estimate likewise precedes rhs(xn).  The sums are the plain
 * sums, term for term in the same order (rk_sum_n), so the result is the same bit for bit. */
LEV_FORCE_INLINE const double *adaptive_stage_arg(adaptive_run *r, int s, const adaptive_method *m,
                                                  const int n, double **dst)
{
    const lev_options *o = r->c->opt;
    const int last = s == m->stages;
    const double *row = last ? m->B : m->A[s], *Knew = r->K + (size_t)(s - 1) * n;
    const double a = (!last || s - 1 < m->n_b) ? row[s - 1] : 0.0;
    const double *next;
    int i, n_old;

    if (a != 0.0)
        for (i = 0; i < n; i++) r->P[i] = LEV_MADD(a, Knew[i], r->P[i]);
    if (last) {
        add_compensated(n, r->x, r->h, r->P, r->comp, r->xn, r->comp_new);
        r->err = m->err(n, normed(r->c->sys), r->K, r->h, r->x, r->xn, o->rtol, o->atol, o->atol_v);
        r->fac = 0.9 * pow(r->err, -m->expo);
        *dst = r->K + (size_t)m->f_slot * n;
        return r->xn;
    }
    for (i = 0; i < n; i++) r->tmp[i] = LEV_MADD(r->h, r->P[i], r->x[i]);
    /* the older part of the next combination: stage s + 1's row, or the solution's weights */
    next = s + 1 < m->stages ? m->A[s + 1] : m->B;
    n_old = s + 1 < m->stages ? s : (s < m->n_b ? s : m->n_b);
    rk_sum_n(n, NULL, 0.0, r->K, next, n_old, r->P);
    *dst = r->K + (size_t)s * n;
    return r->tmp;
}

/* Stage s of one run: its argument (adaptive_stage_arg), then the rhs into its slot of K. */
LEV_FORCE_INLINE void adaptive_stage(adaptive_run *r, int s, const adaptive_method *m, const int n)
{
    double *dst;
    const double *arg = adaptive_stage_arg(r, s, m, n, &dst);
    call_rhs(r->c, arg, dst);
}

/* After the stages: the error estimate, then a rejection (a smaller step, LEV_RUNNING) or the
 * step accepted: the energy monitor, the box event (located on the dense output by bisection),
 * the samples.  LEV_RUNNING or the run's final status. */
static int adaptive_judge(adaptive_run *r)
{
    lev_ctx *c = r->c;
    const lev_options *o = c->opt;
    const adaptive_method *m = r->m;
    lev_stats *st = c->st;
    int n = c->sys->n, dense_ready = 0, it;
    double *x = r->x, *swap, h = r->h, t_old, err, fac, e;

    err = r->err;
    if (!isfinite(err) || !all_finite(r->xn, n) || !all_finite(r->K + (size_t)m->f_slot * n, n)) {
        r->h_abs *= 0.2;
        st->rejected++;
        r->rejected_here = r->last_nonfinite = 1;
        return LEV_RUNNING;
    }
    r->last_nonfinite = 0;
    fac = r->fac;
    if (!(err < 1.0)) {
        r->h_abs *= fmax(0.2, fac);
        st->rejected++;
        r->rejected_here = 1;
        return LEV_RUNNING;
    }
    {
        double factor = (err == 0.0) ? 10.0 : fmin(10.0, fac);
        if (r->rejected_here) factor = fmin(1.0, factor);
        r->h_abs *= factor;
    }
    /* accept */
    r->rejected_here = 0;
    memcpy(r->yo, x, (size_t)n * sizeof(double));
    t_old = r->t;
    memcpy(x, r->xn, (size_t)n * sizeof(double));
    memcpy(r->f, r->K + (size_t)m->f_slot * n, (size_t)n * sizeof(double));
    swap = r->comp;
    r->comp = r->comp_new;
    r->comp_new = swap;
    r->t = r->t_new;
    st->steps++;
    st->h_last = h;
    st->t_final = r->t;
    if (r->h_abs > r->hmax) r->h_abs = r->hmax;
    e = monitor(c, x);

    if (o->box_on && box_outside(o, x)) {
        double lo = 0.0, hi = 1.0;
        m->prepare(c, r->yo, x, r->f, h, r->K, r->F, r->tmp);
        dense_ready = 1;
        for (it = 0; it < 80 && (hi - lo) * h > 2.0 * DBL_EPSILON * fabs(r->t); it++) {
            double mid = 0.5 * (lo + hi);
            m->eval(c, mid, h, r->yo, r->F, r->yd, r->K, r->tmp);
            if (all_finite(r->yd, n) && !box_outside(o, r->yd)) lo = mid; else hi = mid;
        }
        if (hi < 1.0) {
            m->eval(c, hi, h, r->yo, r->F, r->yd, r->K, r->tmp);
            if (all_finite(r->yd, n) && box_outside(o, r->yd)) {
                memcpy(x, r->yd, (size_t)n * sizeof(double));
                r->t = t_old + hi * h;
                st->t_final = r->t;
                e = c->sys->energy ? call_energy(c, x) : 0.0;
            }
        }
        while (o->t_out && r->i_out < o->n_out && o->t_out[r->i_out] < r->t) {
            double th = (o->t_out[r->i_out] - t_old) / h;
            m->eval(c, th, h, r->yo, r->F, r->yd, r->K, r->tmp);
            record(c, o->t_out[r->i_out], r->yd, c->sys->energy ? call_energy(c, r->yd) : 0.0);
            r->i_out++;
        }
        record(c, r->t, x, e);
        return LEV_LEFT_BOX;
    }
    if (energy_exceeded(c)) return LEV_ENERGY_LIMIT;
    if (o->t_out) {
        while (r->i_out < o->n_out && o->t_out[r->i_out] <= r->t) {
            if (o->t_out[r->i_out] == r->t) {
                record(c, r->t, x, e);
            } else {
                double th = (o->t_out[r->i_out] - t_old) / h;
                if (!dense_ready) {
                    m->prepare(c, r->yo, x, r->f, h, r->K, r->F, r->tmp);
                    dense_ready = 1;
                }
                m->eval(c, th, h, r->yo, r->F, r->yd, r->K, r->tmp);
                record(c, o->t_out[r->i_out], r->yd, c->sys->energy ? call_energy(c, r->yd) : 0.0);
            }
            r->i_out++;
        }
    } else if (o->every > 0 && st->steps % o->every == 0) {
        record(c, r->t, x, e);
    }
    return r->t < o->t_end ? LEV_RUNNING : LEV_COMPLETED;
}

/* All stages of an attempt.  Inlined with the method and n constant, and the stage loop unrolled,
 * the tableau's entries become constants in the code: the zero entries vanish, and no loop or
 * branch is left between the rhs calls (about 10% of a step of the full model). */
LEV_FORCE_INLINE void stages_of(adaptive_run *r, const adaptive_method *m, const int n)
{
    int s;
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 17
#endif
    for (s = 1; s <= m->stages; s++) adaptive_stage(r, s, m, n);
}

/* The specialised copies: the two methods for the full (12) and reduced (4) models. */
static void attempt_stages(adaptive_run *r)
{
    const int n = r->c->sys->n;
    if (r->m == &DOP853_M && n == 12) stages_of(r, &DOP853_M, 12);
    else if (r->m == &VERN9_M && n == 12) stages_of(r, &VERN9_M, 12);
    else if (r->m == &DOP853_M && n == 4) stages_of(r, &DOP853_M, 4);
    else if (r->m == &VERN9_M && n == 4) stages_of(r, &VERN9_M, 4);
    else stages_of(r, r->m, n);
}

static int run_adaptive(lev_ctx *c, double *x, double *w, const adaptive_method *m)
{
    adaptive_run r;
    int status = adaptive_start(&r, c, x, w, m);
    while (status == LEV_RUNNING && (status = adaptive_next(&r)) == LEV_RUNNING) {
        attempt_stages(&r);
        status = adaptive_judge(&r);
    }
    return status;
}


/* ---- Taylor's method over the generated coefficients (LEV_TAYLOR) ---- */

int lev_taylor_order(double rtol)
{
    const double p = ceil(-log(rtol) / 2.0 + 1.0);
    if (!(p >= 2.0)) return 2;                      /* also a NaN */
    return p > LEV_TAYLOR_MAX_ORDER ? LEV_TAYLOR_MAX_ORDER : (int)p;
}

/* inc_k = sum_{j=1..p} C_k^[j] h^j (Horner): the change of state k over h from the expansion point. */
static void taylor_increment(int n, int p, const double *C, double h, double *inc)
{
    int k, j;
    for (k = 0; k < n; k++) {
        const double *ck = C + (size_t)k * (size_t)(p + 1);
        double s = ck[p];
        for (j = p - 1; j >= 1; j--) s = LEV_MADD(s, h, ck[j]);
        inc[k] = s * h;
    }
}

/* The state at the expansion point + dt (the step's polynomial: dense output, the box event). */
static void taylor_dense(int n, int p, const double *C, double dt, double *y)
{
    int k;
    taylor_increment(n, p, C, dt, y);
    for (k = 0; k < n; k++) y[k] += C[(size_t)k * (size_t)(p + 1)];
}

/* The step from the coefficients (Jorba & Zou, Experiment. Math. 14, 2005, sec. 3): with the
 * component weights w_k = atol_k / rtol + |x_k| and N_j = max_k |C_k^[j]| / w_k, the radius of
 * convergence is estimated from the last two orders as rho = min(N_{p-1}^(-1/(p-1)), N_p^(-1/p)),
 * so that |C_k^[j]| <~ w_k rho^-j. A step h then errs in component k by about its first omitted
 * term, w_k (h / rho)^(p+1), and h = rho (s rtol)^(1/(p+1)) holds that to s rtol w_k per step, the
 * contract of every adaptive method here (s = LEV_TAYLOR_SAFETY; the order p = ceil(-ln rtol / 2
 * + 1) is Jorba & Zou's). Their own step, rho e^-2 e^(-0.7/(p-1)) (heyoka's), errs by about
 * (h / rho)^(p+1) <= rtol e^-4 e^-0.7 w_k < 0.01 rtol w_k per step: ten times or more below the
 * contract, in more and shorter steps (the bench's reduced runs at tol 1e-8: square 11 -> 8 steps,
 * ring_magnet 8 -> 6, loop 12 -> 8, reduced_only 21 -> 15; errors 2.5e-10 to 1.4e-9 of the scales).
 * `shrink` is (s rtol)^(1/(p+1)), computed once per run; rho comes from one exp of the larger of
 * ln(N_{p-1}) / (p-1) and ln(N_p) / p (the coefficients are finite here: run_taylor checks them
 * first, so the maxima need no NaN rule). */
#define LEV_TAYLOR_SAFETY 0.1
static double taylor_step(int n, int p, const double *C, const double *x, const lev_options *o,
                          double shrink)
{
    double n1 = 0.0, n2 = 0.0, l = -INFINITY;
    int k;
    for (k = 0; k < n; k++) {
        const double *ck = C + (size_t)k * (size_t)(p + 1);
        const double iw = 1.0 / ((o->atol_v ? o->atol_v[k] : o->atol) / o->rtol + fabs(x[k]));
        const double a = fabs(ck[p - 1]) * iw, b = fabs(ck[p]) * iw;
        if (a > n1) n1 = a;
        if (b > n2) n2 = b;
    }
    if (n1 > 0.0) l = log(n1) / (p - 1);
    if (n2 > 0.0 && log(n2) / p > l) l = log(n2) / p;
    return l == -INFINITY ? INFINITY : exp(-l) * shrink;
}

/* After an accepted step from t_old (coefficients C at the old state) to t: the box event located
 * on the step's polynomial by bisection, then the samples; LEV_RUNNING or the final status. */
static int taylor_after_step(lev_ctx *c, int p, const double *C, double t_old, double *t, double h,
                             double *x, double *yd, long *i_out, double e)
{
    const lev_options *o = c->opt;
    lev_stats *st = c->st;
    const int n = c->sys->n;
    int it;
    if (o->box_on && box_outside(o, x)) {
        double lo = 0.0, hi = 1.0;
        for (it = 0; it < 80 && (hi - lo) * h > 2.0 * DBL_EPSILON * fabs(*t); it++) {
            double mid = 0.5 * (lo + hi);
            taylor_dense(n, p, C, mid * h, yd);
            if (all_finite(yd, n) && !box_outside(o, yd)) lo = mid; else hi = mid;
        }
        if (hi < 1.0) {
            taylor_dense(n, p, C, hi * h, yd);
            if (all_finite(yd, n) && box_outside(o, yd)) {
                memcpy(x, yd, (size_t)n * sizeof(double));
                *t = t_old + hi * h;
                st->t_final = *t;
                e = c->sys->energy ? call_energy(c, x) : 0.0;
            }
        }
        while (o->t_out && *i_out < o->n_out && o->t_out[*i_out] < *t) {
            taylor_dense(n, p, C, o->t_out[*i_out] - t_old, yd);
            record(c, o->t_out[*i_out], yd, c->sys->energy ? call_energy(c, yd) : 0.0);
            (*i_out)++;
        }
        record(c, *t, x, e);
        return LEV_LEFT_BOX;
    }
    if (energy_exceeded(c)) return LEV_ENERGY_LIMIT;
    if (o->t_out) {
        while (*i_out < o->n_out && o->t_out[*i_out] <= *t) {
            if (o->t_out[*i_out] == *t) {
                record(c, *t, x, e);
            } else {
                taylor_dense(n, p, C, o->t_out[*i_out] - t_old, yd);
                record(c, o->t_out[*i_out], yd, c->sys->energy ? call_energy(c, yd) : 0.0);
            }
            (*i_out)++;
        }
    } else if (o->every > 0 && st->steps % o->every == 0) {
        record(c, *t, x, e);
    }
    return *t < o->t_end ? LEV_RUNNING : LEV_COMPLETED;
}

/* Taylor's method: at each step the coefficients of order p at x (sys->taylor), the step of
 * taylor_step, the new state by Horner and compensated summation. Every step is accepted (the
 * step is chosen from the coefficients so that the truncation error is about s rtol w_k); one
 * expansion per step (counted in st->iterations), no rhs call. */
static int run_taylor(lev_ctx *c, double *x, double *w)
{
    const lev_options *o = c->opt;
    lev_stats *st = c->st;
    const int n = c->sys->n, p = lev_taylor_order(o->rtol);
    double *C = w, *xn = C + (size_t)n * (size_t)(p + 1), *comp = xn + n, *comp_new = comp + n,
           *yd = comp_new + n, *swap;
    const double hmax = o->h_max > 0.0 ? o->h_max : o->t_end - o->t0;
    const double shrink = pow(LEV_TAYLOR_SAFETY * o->rtol, 1.0 / (p + 1)),
                 stretch = pow(LEV_TAYLOR_SAFETY, -1.0 / (p + 1));
    double t = o->t0;
    long i_out = 0;
    int k, status;
    for (k = 0; k < n; k++) comp[k] = 0.0;
    while (o->t_out && i_out < o->n_out && o->t_out[i_out] <= t) {
        record(c, t, x, st->energy0);
        i_out++;
    }
    for (;;) {
        double h, t_new, t_old, e;
        if (st->steps >= o->max_steps) return LEV_STEP_BUDGET;
        if (c->sys->taylor(x, c->sys->p, p, C) != 0) return LEV_BAD_INPUT;
        st->iterations++;
        if (!all_finite(C, n * (p + 1))) return LEV_NONFINITE;
        h = fmin(taylor_step(n, p, C, x, o, shrink), hmax);
        /* the last step may go without the safety factor (to rtol w_k rather than s rtol w_k) rather
         * than leave a sliver that costs one more expansion (as DOP853 stretches its last step by 1 %) */
        if (o->t_end - t <= h * stretch && o->t_end - t <= hmax) h = o->t_end - t;
        t_new = t + h < o->t_end ? t + h : o->t_end;
        h = t_new - t;
        if (!(h > 0.0) || h < 10.0 * (nextafter(t, INFINITY) - t))
            return LEV_STEP_UNDERFLOW;
        taylor_increment(n, p, C, h, yd);
        add_compensated(n, x, 1.0, yd, comp, xn, comp_new);
        if (!all_finite(xn, n)) return LEV_NONFINITE;
        memcpy(x, xn, (size_t)n * sizeof(double));
        swap = comp;
        comp = comp_new;
        comp_new = swap;
        t_old = t;
        t = t_new;
        st->steps++;
        st->h_last = h;
        st->t_final = t;
        e = monitor(c, x);
        status = taylor_after_step(c, p, C, t_old, &t, h, x, yd, &i_out, e);
        if (status != LEV_RUNNING) return status;
    }
}

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

/* ---- driver ---- */

/* lev_integrate's checks and its first sample: LEV_RUNNING, or the status of a run that ends here
 * (st->status set).  c is filled for the method's loop. */
static int integrate_begin(int method, const lev_system *sys, const lev_options *opt, double *x,
                           void *work, double *out_t, double *out_x, double *out_e, lev_stats *st,
                           lev_ctx *c)
{
    int fixed, n;
    double e0 = 0.0;

    if (!st) return LEV_BAD_INPUT;
    memset(st, 0, sizeof *st);
    st->t_final = opt ? opt->t0 : 0.0;
    st->status = LEV_BAD_INPUT;
    if (!sys || !opt || !x || !work || !sys->rhs || sys->n <= 0 || sys->n > LEV_MAX_STATES)
        return LEV_BAD_INPUT;
    n = sys->n;
    fixed = lev_method_fixed_step(method);
    if (fixed < 0) return LEV_BAD_INPUT;
    if (opt->max_steps <= 0) return LEV_BAD_INPUT;      /* every run has a step budget */
    if (!(opt->t_end > opt->t0) || !isfinite(opt->t0) || !isfinite(opt->t_end)) return LEV_BAD_INPUT;
    if (fixed && (!(opt->h > 0.0) || !isfinite(opt->h))) return LEV_BAD_INPUT;
    if (fixed && opt->t_out) return LEV_BAD_INPUT;
    if (method == LEV_TAYLOR && (!sys->taylor || !(opt->rtol > 0.0) || sys->quad)) return LEV_BAD_INPUT;
    if (sys->quad && n < 2) return LEV_BAD_INPUT;
    if (!fixed && (!(opt->rtol >= 0.0) || !(opt->atol >= 0.0) || !(opt->h >= 0.0)
                   || !(opt->h_max >= 0.0)))
        return LEV_BAD_INPUT;
    if (!fixed) {
        int k;
        for (k = 0; k < n; k++) {
            double a = opt->atol_v ? opt->atol_v[k] : opt->atol;
            if (!(a >= 0.0) || !isfinite(a) || !(a + opt->rtol > 0.0)) return LEV_BAD_INPUT;
        }
    }
    if (opt->max_samples < 0 || (opt->box_on && (opt->iz >= n || opt->ix >= n || opt->iy >= n)))
        return LEV_BAD_INPUT;
    if (!all_finite(x, n)) return LEV_BAD_INPUT;

    c->sys = sys;
    c->opt = opt;
    c->st = st;
    c->out_t = out_t;
    c->out_x = out_x;
    c->out_e = out_e;
    c->t_last_rec = 0.0;
    c->recorded_any = 0;

    if (sys->energy) {
        e0 = call_energy(c, x);
        st->energy0 = e0;
    }
    if (!opt->t_out) record(c, opt->t0, x, e0);
    if (outside(opt, x)) {
        st->status = LEV_LEFT_BOX;
        return st->status;
    }
    return LEV_RUNNING;
}

/* The last sample of a run that went through its method's loop; st->status. */
static int integrate_end(lev_ctx *c, double *x, int status)
{
    const lev_system *sys = c->sys;
    if (!c->opt->t_out || status != LEV_COMPLETED)
        record(c, c->st->t_final, x, sys->energy ? call_energy(c, x) : 0.0);
    c->st->status = status;
    return status;
}

int lev_integrate(int method, const lev_system *sys, const lev_options *opt, double *x,
                  void *work, double *out_t, double *out_x, double *out_e, lev_stats *st)
{
    lev_ctx c;
    int status = integrate_begin(method, sys, opt, x, work, out_t, out_x, out_e, st, &c);
    if (status != LEV_RUNNING) return status;
    if (method == LEV_DOP853)
        status = run_adaptive(&c, x, (double *)work, &DOP853_M);
    else if (method == LEV_VERN9)
        status = run_adaptive(&c, x, (double *)work, &VERN9_M);
    else if (method == LEV_TAYLOR)
        status = run_taylor(&c, x, (double *)work);
    else if (method == LEV_GAUSS4 || method == LEV_MIDPOINT)
        status = run_gauss(method, &c, x, (double *)work);
    else
        status = run_fixed(method, &c, x, (double *)work);
    return integrate_end(&c, x, status);
}

int lev_integrate_job(const lev_job *job)
{
    if (!job) return LEV_BAD_INPUT;
    return lev_integrate(job->method, job->sys, job->opt, job->x, job->work, job->out_t, job->out_x,
                         job->out_e, job->st);
}

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

/* ---- timing ---- */

double lev_time_fn(lev_fn f, const double *x, const double *p, int n_out, long reps)
{
    double out[4096];
    struct timespec a, b;
    long r;
    volatile double sink;
    if (n_out < 1 || n_out > 4096 || reps < 1 || !f) return -1.0;
    clock_gettime(CLOCK_MONOTONIC, &a);
    for (r = 0; r < reps; r++) f(x, p, out);
    clock_gettime(CLOCK_MONOTONIC, &b);
    sink = out[0];
    (void)sink;
    return ((double)(b.tv_sec - a.tv_sec) * 1e9 + (double)(b.tv_nsec - a.tv_nsec)) / (double)reps;
}
