/*
 * The robot-to-robot dispatcher: measurement model, classification into the
 * 14 base systems of Zhou & Roumeliotis (T-RO 2013), and sfm_r2r_solve.
 *
 * Reduction. A sequence of exactly six scalar equations is brought to its
 * base system by the two symmetries of the problem: exchanging the robots
 * ((C, p) -> (C^T, -C^T p), b1 <-> b2, ego-motions swapped) and
 * re-referencing to another step (the step placed first becomes frames {1}
 * and {2}; see solvers/r2r_solve_internal.h for the maps). Canonical step
 * order: rank {d,b1,b2} < {b1,b2} < {d,b1} < {d,b2} < {b1} < {b2} < {d},
 * stable among equal masks; the exchange is used only when the unexchanged
 * order is not one of the 14 patterns.
 *
 * Steps at the same positions. Two steps where both robots occupy the same
 * positions (t1 and t2 equal within 1e-9 of the scene's scale) observe one
 * relative vector v = C t2 + p - t1: their distances are equal and their
 * bearings differ only by the known rotations R1_a^T R1_b (R2_a^T R2_b).
 * They are merged into one step before anything else (bearings rotated into
 * the first step's frame); a measurement repeated at the same positions
 * adds no equation. This is how "both robots standing still" (or returning
 * to the same places) is recognised.
 *
 * Degenerate motion (SFM_E_DEGENERATE, never an answer), detected cheaply:
 *  - fewer than six independent equations once repeated measurements at the
 *    same positions are merged (robots standing still, only rotating);
 *  - robot 2's positions on one straight line (within 1e-6 of the scale;
 *    standing still included) and no bearing b2: with u the line's
 *    direction, every measurement sees only C u and C t2_0 + p, so
 *    (Q C, p + (I - Q) C t2_0) for any turn Q about C u fits them all, a
 *    continuum. Likewise robot 1 on a line and no b1 (exchange the robots).
 *    This covers distances only with parallel straight-line motion or one
 *    robot still, bearings from one robot only while the other is still,
 *    and {d,b1} {d,b1} (two positions always lie on a line);
 *  - the base system's template singular for these data (SFM_E_SINGULAR
 *    from the solver).
 *
 * Candidates. Every solution is checked on all measurements through
 * sfm_r2r_predict with a dimensionless residual: each distance contributes
 * (d_pred - d) / d, each bearing the chord |b_pred - b| (radians for small
 * errors), so a lateral error e at range d weighs e / d either way; the
 * score is the RMS over the scalar equations. With exactly six equations a
 * candidate scoring above 1e-4 is a numerical artefact of the solver and is
 * dropped (an exact solution of noisy minimal data scores near zero).
 *
 * More than six equations: a minimal subset is chosen by a fixed rule, then
 * its candidates are verified on all measurements. Rule: base systems are
 * tried in enum order (more equations on fewer steps first: the direct
 * measurements of one step depend least on ego-motion drift, and the first
 * systems have closed forms), each with the robots as given and exchanged;
 * the first canonical step is the earliest step carrying its measurements,
 * each further step the unused one farthest (|dt1| + |dt2|, the motion of
 * both robots) from the steps already chosen, the widest baseline. A subset
 * that is degenerate by the line rule is skipped (so are the patterns of
 * rank-deficient systems, and the exchanged copy of a pattern the exchange
 * maps onto itself). Up to three subsets whose best candidate scores at
 * most 0.05 are solved (the search stops at once when one fits the data to
 * 1e-9, noise-free data); the subset with the lowest best score wins, and
 * its candidates scoring at most 0.05 and at most 4 times that best (plus
 * 1e-9) are returned, best first. Comparing three subsets rather than
 * taking the first lowers the error of the answer on noisy data (figures in
 * bench/README.md).
 *
 * Stack: under 4 KiB (two sfmi_r2r_canon and scratch); the solvers' work
 * memory comes from ws (the largest ws_doubles of the registry).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/linalg_util.h"
#include "core/arena.h"
#include "sfm/sfm_r2r.h"
#include "solvers/r2r_solve_internal.h"
#include "solvers/small_math.h"

#define ROT_TOL 1e-6        /* |R R^T - I| entries of a valid ego-motion rotation */
#define SAME_POS_TOL 1e-9   /* relative: steps at the same positions */
#define LINE_TOL 1e-6       /* relative: positions on one straight line */
#define EXACT_TOL 1e-4      /* score of a solution of exactly six equations */
#define GATE_TOL 0.05       /* score of a verified candidate, more than six */
#define GATE_FACTOR 4.0
#define SUBSETS 3           /* subsets with a kept candidate compared, more than six */
#define EXACT_FIT 1e-9      /* a score this small ends the subset search */

/* ---- The registry -------------------------------------------------------- */

int sfmi_r2r_solve_rank5(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)steps;
    (void)out;
    (void)ws;
    return SFM_E_DEGENERATE;
}

const sfmi_r2r_registry sfmi_r2r_table = {
    NULL,
    &sfmi_r2r_db1b2_d,
    &sfmi_r2r_b1b2_b1,
    &sfmi_r2r_b1b2_d_d,
    &sfmi_r2r_db1_db1,
    &sfmi_r2r_db1_db2,
    &sfmi_r2r_db1_b1_d,
    &sfmi_r2r_db1_b2_d,
    &sfmi_r2r_db1_d_d_d,
    &sfmi_r2r_b1_b1_b1,
    &sfmi_r2r_b1_b1_b2,
    &sfmi_r2r_b1_b1_d_d,
    &sfmi_r2r_b1_b2_d_d,
    &sfmi_r2r_b1_d_d_d_d,
    &sfmi_r2r_d6,
};

#define D_ SFM_R2R_D
#define B1_ SFM_R2R_B1
#define B2_ SFM_R2R_B2

const unsigned char sfmi_r2r_patterns[SFM_R2R_SYS_COUNT_][7] = {
    {0, 0, 0, 0, 0, 0, 0},
    {2, D_ | B1_ | B2_, D_, 0, 0, 0, 0}, /* DB1B2_D */
    {2, B1_ | B2_, B1_, 0, 0, 0, 0},     /* B1B2_B1 */
    {3, B1_ | B2_, D_, D_, 0, 0, 0},     /* B1B2_D_D */
    {2, D_ | B1_, D_ | B1_, 0, 0, 0, 0}, /* DB1_DB1 */
    {2, D_ | B1_, D_ | B2_, 0, 0, 0, 0}, /* DB1_DB2 */
    {3, D_ | B1_, B1_, D_, 0, 0, 0},     /* DB1_B1_D */
    {3, D_ | B1_, B2_, D_, 0, 0, 0},     /* DB1_B2_D */
    {4, D_ | B1_, D_, D_, D_, 0, 0},     /* DB1_D_D_D */
    {3, B1_, B1_, B1_, 0, 0, 0},         /* B1_B1_B1 */
    {3, B1_, B1_, B2_, 0, 0, 0},         /* B1_B1_B2 */
    {4, B1_, B1_, D_, D_, 0, 0},         /* B1_B1_D_D */
    {4, B1_, B2_, D_, D_, 0, 0},         /* B1_B2_D_D */
    {5, B1_, D_, D_, D_, D_, 0},         /* B1_D_D_D_D */
    {6, D_, D_, D_, D_, D_, D_},         /* D6 */
};

/* ---- Small helpers ---------------------------------------------------------- */

static int n_eq(unsigned m)
{
    return ((m & D_) ? 1 : 0) + ((m & B1_) ? 2 : 0) + ((m & B2_) ? 2 : 0);
}

static unsigned swap_bits(unsigned m)
{
    return (m & D_) | ((m & B1_) ? B2_ : 0u) | ((m & B2_) ? B1_ : 0u);
}

/* Canonical order of a step's mask (index 0..6), 7 for an unused step. */
static int mask_rank(unsigned m)
{
    static const signed char rank[8] = {7, 6, 4, 2, 5, 3, 1, 0};
    return rank[m & 7u];
}

static double norm3(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static double dist3(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return norm3(d);
}

/* Arguments of every step: the statuses of sfm_r2r_classify / solve. Writes
 * the number of scalar equations. */
static int check_steps(const sfm_r2r_step *s, int n, int *eqs)
{
    int e = 0;
    for (int k = 0; k < n; k++) {
        const sfm_r2r_step *st = s + k;
        if (st->has & ~7u)
            return SFM_E_ARGUMENT;
        if (!sfmi_la_all_finite(st->R1.m, 9) || !sfmi_la_all_finite(st->t1.v, 3) || !sfmi_la_all_finite(st->R2.m, 9) ||
            !sfmi_la_all_finite(st->t2.v, 3))
            return SFM_E_NONFINITE;
        if (((st->has & D_) && !isfinite(st->d)) || ((st->has & B1_) && !sfmi_la_all_finite(st->b1.v, 3)) ||
            ((st->has & B2_) && !sfmi_la_all_finite(st->b2.v, 3)))
            return SFM_E_NONFINITE;
    }
    for (int k = 0; k < n; k++) {
        const sfm_r2r_step *st = s + k;
        if (!sfmi_la_is_rotation(st->R1.m, ROT_TOL) || !sfmi_la_is_rotation(st->R2.m, ROT_TOL))
            return SFM_E_ARGUMENT;
        if ((st->has & D_) && !(st->d > 0.0))
            return SFM_E_ARGUMENT;
        if ((st->has & B1_) && !(norm3(st->b1.v) > 0.0))
            return SFM_E_ARGUMENT;
        if ((st->has & B2_) && !(norm3(st->b2.v) > 0.0))
            return SFM_E_ARGUMENT;
        e += n_eq(st->has);
    }
    *eqs = e;
    return SFM_OK;
}

static double scene_scale(const sfm_r2r_step *s, int n)
{
    double sc = 1.0;
    for (int k = 0; k < n; k++)
        for (int i = 0; i < 3; i++) {
            sc = fabs(s[k].t1.v[i]) > sc ? fabs(s[k].t1.v[i]) : sc;
            sc = fabs(s[k].t2.v[i]) > sc ? fabs(s[k].t2.v[i]) : sc;
        }
    return sc;
}

static void unit3(const double *b, double *u)
{
    double s = 1.0 / norm3(b);
    u[0] = b[0] * s;
    u[1] = b[1] * s;
    u[2] = b[2] * s;
}

/* Steps with measurements, merged where both robots are at the same
 * positions; bearings unit. Returns the merged count. */
static int merge_steps(const sfm_r2r_step *s, int n, sfm_r2r_step *m)
{
    double tol = SAME_POS_TOL * scene_scale(s, n);
    int nm = 0;
    for (int k = 0; k < n; k++) {
        const sfm_r2r_step *st = s + k;
        if (!st->has)
            continue;
        int g = -1;
        for (int j = 0; j < nm && g < 0; j++)
            if (dist3(m[j].t1.v, st->t1.v) <= tol && dist3(m[j].t2.v, st->t2.v) <= tol)
                g = j;
        if (g < 0) {
            m[nm] = *st;
            m[nm].has = 0;
            g = nm++;
        }
        sfm_r2r_step *t = m + g;
        double u[3], R[9];
        if ((st->has & D_) && !(t->has & D_)) {
            t->d = st->d;
            t->has |= D_;
        }
        if ((st->has & B1_) && !(t->has & B1_)) {
            unit3(st->b1.v, u);
            sfmi_matmul3_tn(t->R1.m, st->R1.m, R);
            sfmi_matvec3(R, u, t->b1.v);
            t->has |= B1_;
        }
        if ((st->has & B2_) && !(t->has & B2_)) {
            unit3(st->b2.v, u);
            sfmi_matmul3_tn(t->R2.m, st->R2.m, R);
            sfmi_matvec3(R, u, t->b2.v);
            t->has |= B2_;
        }
    }
    return nm;
}

/* Points on one line (within tol): the farthest point from the first sets
 * the direction. */
static int collinear(const sfm_r2r_step *s, const unsigned *use, int n, int robot, double tol)
{
    const double *a = NULL, *b = NULL;
    double far = -1.0;
    for (int k = 0; k < n; k++) {
        if (use && !use[k])
            continue;
        const double *x = robot == 1 ? s[k].t1.v : s[k].t2.v;
        if (!a)
            a = x;
        double dd = dist3(a, x);
        if (dd > far) {
            far = dd;
            b = x;
        }
    }
    if (!a || far <= tol)
        return 1;
    double u[3] = {(b[0] - a[0]) / far, (b[1] - a[1]) / far, (b[2] - a[2]) / far};
    for (int k = 0; k < n; k++) {
        if (use && !use[k])
            continue;
        const double *x = robot == 1 ? s[k].t1.v : s[k].t2.v;
        double w[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
        double l = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
        double q[3] = {w[0] - l * u[0], w[1] - l * u[1], w[2] - l * u[2]};
        if (norm3(q) > tol)
            return 0;
    }
    return 1;
}

/* A turn of C about robot 2's line of motion that no measurement sees:
 * robot 2's positions on one line and no b2, or robot 1's on one line and
 * no b1 (see the header comment). */
int sfmi_r2r_motion_degenerate(const sfm_r2r_step *s, const unsigned *use, int n)
{
    unsigned any = 0;
    for (int k = 0; k < n; k++)
        any |= use ? use[k] : s[k].has;
    double tol = LINE_TOL * scene_scale(s, n);
    return (!(any & B2_) && collinear(s, use, n, 2, tol)) || (!(any & B1_) && collinear(s, use, n, 1, tol));
}

/* ---- The measurement model ------------------------------------------------ */

SFM_API int sfm_r2r_predict(const sfm_r2r_step *step, const sfm_r2r_transform *T, double *d,
                            sfm_vec3 *b1, sfm_vec3 *b2)
{
    if (!step || !T)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(step->R1.m, 9) || !sfmi_la_all_finite(step->t1.v, 3) || !sfmi_la_all_finite(step->R2.m, 9) ||
        !sfmi_la_all_finite(step->t2.v, 3) || !sfmi_la_all_finite(T->C.m, 9) || !sfmi_la_all_finite(T->p.v, 3))
        return SFM_E_NONFINITE;
    double v[3], w[3], u1[3], u2[3];
    sfmi_matvec3(T->C.m, step->t2.v, v);
    for (int i = 0; i < 3; i++)
        v[i] += T->p.v[i] - step->t1.v[i];
    double r = norm3(v);
    if ((b1 || b2) && !(r > 0.0))
        return SFM_E_SINGULAR;
    if (b1 || b2) {
        sfmi_matvec3_t(step->R1.m, v, u1);
        sfmi_matvec3_t(T->C.m, v, w); /* C^T (t1 - p) - t2 = -C^T v */
        sfmi_matvec3_t(step->R2.m, w, u2);
        for (int i = 0; i < 3; i++) {
            u1[i] /= r;
            u2[i] = -u2[i] / r;
        }
        if (!sfmi_la_all_finite(u1, 3) || !sfmi_la_all_finite(u2, 3))
            return SFM_E_NONFINITE;
    }
    if (!isfinite(r))
        return SFM_E_NONFINITE;
    if (d)
        *d = r;
    if (b1)
        memcpy(b1->v, u1, sizeof u1);
    if (b2)
        memcpy(b2->v, u2, sizeof u2);
    return SFM_OK;
}

/* ---- Canonical form ---------------------------------------------------------- */

int sfmi_r2r_canonicalize(const sfm_r2r_step *steps, const unsigned *use, int n, sfmi_r2r_canon *c)
{
    int idx[6], cnt = 0, e = 0;
    for (int k = 0; k < n; k++) {
        if (!use[k])
            continue;
        if (cnt == 6)
            return SFM_E_ARGUMENT;
        idx[cnt++] = k;
        e += n_eq(use[k]);
    }
    if (e != 6)
        return SFM_E_ARGUMENT;
    for (int swap = 0; swap < 2; swap++) {
        int ord[6];
        unsigned msk[6];
        for (int i = 0; i < cnt; i++) {
            ord[i] = idx[i];
            msk[i] = swap ? swap_bits(use[idx[i]]) : use[idx[i]];
        }
        for (int i = 1; i < cnt; i++) /* stable insertion sort by rank */
            for (int j = i; j > 0 && mask_rank(msk[j]) < mask_rank(msk[j - 1]); j--) {
                unsigned tm = msk[j];
                int to = ord[j];
                msk[j] = msk[j - 1];
                ord[j] = ord[j - 1];
                msk[j - 1] = tm;
                ord[j - 1] = to;
            }
        int sys = 0;
        for (int s = 1; s < SFM_R2R_SYS_COUNT_ && !sys; s++) {
            if (sfmi_r2r_patterns[s][0] != cnt)
                continue;
            int ok = 1;
            for (int i = 0; i < cnt && ok; i++)
                ok = sfmi_r2r_patterns[s][1 + i] == msk[i];
            if (ok)
                sys = s;
        }
        if (!sys)
            continue;
        c->sys = sys;
        c->swap = swap;
        c->n = cnt;
        const sfm_r2r_step *ref = steps + ord[0];
        memcpy(c->R1r, swap ? ref->R2.m : ref->R1.m, sizeof c->R1r);
        memcpy(c->t1r, swap ? ref->t2.v : ref->t1.v, sizeof c->t1r);
        memcpy(c->R2r, swap ? ref->R1.m : ref->R2.m, sizeof c->R2r);
        memcpy(c->t2r, swap ? ref->t1.v : ref->t2.v, sizeof c->t2r);
        for (int i = 0; i < cnt; i++) {
            const sfm_r2r_step *s = steps + ord[i];
            sfm_r2r_step *o = c->steps + i;
            const double *R1 = swap ? s->R2.m : s->R1.m, *t1 = swap ? s->t2.v : s->t1.v;
            const double *R2 = swap ? s->R1.m : s->R2.m, *t2 = swap ? s->t1.v : s->t2.v;
            const double *b1 = swap ? s->b2.v : s->b1.v, *b2 = swap ? s->b1.v : s->b2.v;
            double dt[3];
            memset(o, 0, sizeof *o);
            c->idx[i] = ord[i];
            o->has = msk[i];
            if (i == 0) {
                o->R1.m[0] = o->R1.m[4] = o->R1.m[8] = 1.0;
                o->R2.m[0] = o->R2.m[4] = o->R2.m[8] = 1.0;
            } else {
                sfmi_matmul3_tn(c->R1r, R1, o->R1.m);
                sfmi_matmul3_tn(c->R2r, R2, o->R2.m);
                for (int j = 0; j < 3; j++)
                    dt[j] = t1[j] - c->t1r[j];
                sfmi_matvec3_t(c->R1r, dt, o->t1.v);
                for (int j = 0; j < 3; j++)
                    dt[j] = t2[j] - c->t2r[j];
                sfmi_matvec3_t(c->R2r, dt, o->t2.v);
            }
            if (msk[i] & D_)
                o->d = s->d;
            if (msk[i] & B1_)
                unit3(b1, o->b1.v);
            if (msk[i] & B2_)
                unit3(b2, o->b2.v);
        }
        return sys;
    }
    return SFM_E_ARGUMENT; /* unreachable: every six-equation pattern is one of the 14 */
}

void sfmi_r2r_to_canonical(const sfmi_r2r_canon *c, const sfm_r2r_transform *in,
                           sfm_r2r_transform *out)
{
    double Cs[9], ps[3], q[3];
    if (c->swap) {
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                Cs[3 * r + k] = in->C.m[3 * k + r];
        sfmi_matvec3(Cs, in->p.v, ps);
        ps[0] = -ps[0];
        ps[1] = -ps[1];
        ps[2] = -ps[2];
    } else {
        memcpy(Cs, in->C.m, sizeof Cs);
        memcpy(ps, in->p.v, sizeof ps);
    }
    sfmi_matvec3(Cs, c->t2r, q);
    for (int i = 0; i < 3; i++)
        q[i] += ps[i] - c->t1r[i];
    sfmi_matvec3_t(c->R1r, q, out->p.v);
    sfmi_matmul3_tn(c->R1r, Cs, Cs);
    sfmi_matmul3(Cs, c->R2r, out->C.m);
}

void sfmi_r2r_from_canonical(const sfmi_r2r_canon *c, const sfm_r2r_transform *in,
                             sfm_r2r_transform *out)
{
    double Cs[9], ps[3], q[3];
    sfmi_matmul3(c->R1r, in->C.m, Cs);
    sfmi_matmul3_nt(Cs, c->R2r, Cs);
    sfmi_matvec3(c->R1r, in->p.v, ps);
    sfmi_matvec3(Cs, c->t2r, q);
    for (int i = 0; i < 3; i++)
        ps[i] += c->t1r[i] - q[i];
    if (c->swap) {
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                out->C.m[3 * r + k] = Cs[3 * k + r];
        sfmi_matvec3(out->C.m, ps, out->p.v);
        out->p.v[0] = -out->p.v[0];
        out->p.v[1] = -out->p.v[1];
        out->p.v[2] = -out->p.v[2];
    } else {
        memcpy(out->C.m, Cs, sizeof Cs);
        memcpy(out->p.v, ps, sizeof ps);
    }
}

/* ---- Classification ---------------------------------------------------------- */

SFM_API int sfm_r2r_classify(const sfm_r2r_step *steps, int n_steps)
{
    if (!steps || n_steps < 1)
        return SFM_E_ARGUMENT;
    int e, st = check_steps(steps, n_steps, &e);
    if (st < 0)
        return st;
    if (e != 6)
        return SFM_E_ARGUMENT;
    sfm_r2r_step m[6]; /* six equations: at most six steps carry any */
    unsigned use[6];
    int nm = merge_steps(steps, n_steps, m), em = 0;
    for (int k = 0; k < nm; k++) {
        use[k] = m[k].has;
        em += n_eq(m[k].has);
    }
    if (em < 6)
        return SFM_E_DEGENERATE;
    sfmi_r2r_canon c;
    return sfmi_r2r_canonicalize(m, use, nm, &c);
}

/* ---- Solving ------------------------------------------------------------------ */

typedef struct r2r_work {
    sfm_r2r_step *m;          /* merged steps */
    unsigned *use;            /* subset masks over m */
    sfm_r2r_transform *cand;  /* candidates of one subset */
    double *score;
    sfm_r2r_transform *bcand; /* the best subset's candidates so far */
    double *bscore;
    double *sws;              /* the base solver's memory */
} r2r_work;

static size_t solver_ws_doubles(const sfmi_r2r_system_desc *const *table)
{
    size_t w = 1;
    for (int s = 1; s < SFM_R2R_SYS_COUNT_; s++)
        if (table[s] && table[s]->ws_doubles > w)
            w = table[s]->ws_doubles;
    return w;
}

static void layout(sfmi_arena *a, const sfmi_r2r_system_desc *const *table, int n, r2r_work *w)
{
    w->m = SFM_ARENA_ARRAY(a, sfm_r2r_step, n);
    w->use = SFM_ARENA_ARRAY(a, unsigned, n);
    w->cand = SFM_ARENA_ARRAY(a, sfm_r2r_transform, SFM_R2R_MAX_SOLUTIONS);
    w->score = SFM_ARENA_ARRAY(a, double, SFM_R2R_MAX_SOLUTIONS);
    w->bcand = SFM_ARENA_ARRAY(a, sfm_r2r_transform, SFM_R2R_MAX_SOLUTIONS);
    w->bscore = SFM_ARENA_ARRAY(a, double, SFM_R2R_MAX_SOLUTIONS);
    w->sws = SFM_ARENA_ARRAY(a, double, solver_ws_doubles(table));
}

/* Step counts whose work memory would not fit a size_t (32-bit targets). */
static int too_many_steps(int n_steps)
{
    return (size_t)n_steps > SIZE_MAX / 4 / (sizeof(sfm_r2r_step) + sizeof(unsigned));
}

size_t sfmi_r2r_solve_ws_size_with(const sfmi_r2r_system_desc *const *table, int n_steps)
{
    if (n_steps < 1 || too_many_steps(n_steps))
        return 0;
    sfmi_arena a;
    r2r_work w;
    sfmi_arena_measure(&a);
    layout(&a, table, n_steps, &w);
    return sfmi_arena_required(&a);
}

SFM_API size_t sfm_r2r_solve_workspace_size(int n_steps)
{
    return sfmi_r2r_solve_ws_size_with(sfmi_r2r_table, n_steps);
}

/* RMS of the dimensionless residuals of T on all measurements. */
static double score_all(const sfm_r2r_step *s, int n, const sfm_r2r_transform *T)
{
    if (!sfmi_la_all_finite(T->C.m, 9) || !sfmi_la_all_finite(T->p.v, 3))
        return HUGE_VAL;
    double sum = 0.0;
    int e = 0;
    for (int k = 0; k < n; k++) {
        unsigned h = s[k].has;
        if (!h)
            continue;
        double d;
        sfm_vec3 b1, b2;
        if (sfm_r2r_predict(s + k, T, &d, &b1, &b2) < 0)
            return HUGE_VAL;
        if (h & D_) {
            double r = (d - s[k].d) / s[k].d;
            sum += r * r;
        }
        if (h & B1_) {
            double u[3];
            unit3(s[k].b1.v, u);
            for (int i = 0; i < 3; i++)
                sum += (b1.v[i] - u[i]) * (b1.v[i] - u[i]);
        }
        if (h & B2_) {
            double u[3];
            unit3(s[k].b2.v, u);
            for (int i = 0; i < 3; i++)
                sum += (b2.v[i] - u[i]) * (b2.v[i] - u[i]);
        }
        e += n_eq(h);
    }
    return sqrt(sum / (double)e);
}

/* Solves the canonical subset c; candidates in the input frames, scored on
 * all steps. Returns the count or the solver's status. */
static int solve_subset(const sfmi_r2r_system_desc *const *table, const sfmi_r2r_canon *c,
                        const sfm_r2r_step *steps, int n_steps, r2r_work *w)
{
    const sfmi_r2r_system_desc *d = table[c->sys];
    if (!d || !d->solve)
        return SFM_E_UNSUPPORTED;
    int k = d->solve(c->steps, w->cand, w->sws);
    if (k < 0)
        return k == SFM_E_SINGULAR ? SFM_E_DEGENERATE : k;
    if (k > SFM_R2R_MAX_SOLUTIONS)
        k = SFM_R2R_MAX_SOLUTIONS;
    for (int i = 0; i < k; i++) {
        sfmi_r2r_from_canonical(c, w->cand + i, w->cand + i);
        w->score[i] = score_all(steps, n_steps, w->cand + i);
    }
    return k;
}

/* Keeps candidates with score <= limit (and finite), best first, into out. */
static int emit(r2r_work *w, int k, double limit, sfm_r2r_transform *out)
{
    int order[SFM_R2R_MAX_SOLUTIONS], m = 0;
    for (int i = 0; i < k; i++) {
        if (!(w->score[i] <= limit))
            continue;
        int j = m++;
        for (; j > 0 && w->score[order[j - 1]] > w->score[i]; j--)
            order[j] = order[j - 1];
        order[j] = i;
    }
    for (int i = 0; i < m; i++)
        out[i] = w->cand[order[i]];
    return m;
}

/* The subset of pattern sys (robots exchanged when swap) over the merged
 * steps, by the rule in the header comment. 1 when it exists. */
static int pick_subset(const sfm_r2r_step *m, int nm, int sys, int swap, unsigned *use)
{
    const unsigned char *pat = sfmi_r2r_patterns[sys];
    int chosen[6], nc = 0;
    memset(use, 0, sizeof(unsigned) * (size_t)nm);
    for (int i = 0; i < pat[0]; i++) {
        unsigned need = swap ? swap_bits(pat[1 + i]) : pat[1 + i];
        int best = -1;
        double bestv = -1.0;
        for (int k = 0; k < nm; k++) {
            if (use[k] || (m[k].has & need) != need)
                continue;
            double v = HUGE_VAL;
            for (int j = 0; j < nc; j++) {
                double dd = dist3(m[k].t1.v, m[chosen[j]].t1.v) + dist3(m[k].t2.v, m[chosen[j]].t2.v);
                v = dd < v ? dd : v;
            }
            if (nc == 0) {
                best = k;
                break;
            }
            if (v > bestv) {
                bestv = v;
                best = k;
            }
        }
        if (best < 0)
            return 0;
        use[best] = need;
        chosen[nc++] = best;
    }
    return 1;
}

int sfmi_r2r_solve_with(const sfmi_r2r_system_desc *const *table, const sfm_r2r_step *steps,
                        int n_steps, sfm_r2r_transform *out, void *ws, size_t ws_size)
{
    if (!table || !steps || n_steps < 1 || !out || !ws)
        return SFM_E_ARGUMENT;
    int e, st = check_steps(steps, n_steps, &e);
    if (st < 0)
        return st;
    if (e < 6)
        return SFM_E_ARGUMENT;
    if (too_many_steps(n_steps))
        return SFM_E_CAPACITY;
    sfmi_arena a;
    r2r_work w;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, table, n_steps, &w);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;

    int nm = merge_steps(steps, n_steps, w.m), em = 0;
    for (int k = 0; k < nm; k++)
        em += n_eq(w.m[k].has);
    if (em < 6 || sfmi_r2r_motion_degenerate(w.m, NULL, nm))
        return SFM_E_DEGENERATE;

    sfmi_r2r_canon c;
    if (em == 6) {
        for (int k = 0; k < nm; k++)
            w.use[k] = w.m[k].has;
        if (sfmi_r2r_canonicalize(w.m, w.use, nm, &c) < 0)
            return SFM_E_ARGUMENT;
        int k = solve_subset(table, &c, steps, n_steps, &w);
        if (k < 0)
            return k;
        return emit(&w, k, EXACT_TOL, out);
    }

    int solved = 0, singular = 0, other = 0, kept = 0, nbest = 0;
    double best_all = HUGE_VAL;
    for (int sys = 1; sys < SFM_R2R_SYS_COUNT_ && kept < SUBSETS; sys++) {
        if (!table[sys] || table[sys]->max_solutions == 0)
            continue; /* not built, or rank-deficient: no subset of it is tried */
        int symmetric = 1;
        for (int i = 0; i < sfmi_r2r_patterns[sys][0]; i++)
            symmetric &= swap_bits(sfmi_r2r_patterns[sys][1 + i]) == sfmi_r2r_patterns[sys][1 + i];
        for (int swap = 0; swap < 2 - symmetric && kept < SUBSETS; swap++) {
            if (!pick_subset(w.m, nm, sys, swap, w.use))
                continue;
            if (sfmi_r2r_motion_degenerate(w.m, w.use, nm))
                continue;
            if (sfmi_r2r_canonicalize(w.m, w.use, nm, &c) < 0)
                continue;
            int k = solve_subset(table, &c, steps, n_steps, &w);
            if (k < 0) {
                if (k == SFM_E_DEGENERATE)
                    singular = 1;
                else
                    other = k;
                continue;
            }
            solved = 1;
            double best = HUGE_VAL;
            for (int i = 0; i < k; i++)
                best = w.score[i] < best ? w.score[i] : best;
            if (!(best <= GATE_TOL))
                continue;
            kept++;
            if (best < best_all) { /* this subset's candidates become the answer */
                best_all = best;
                nbest = k;
                memcpy(w.bcand, w.cand, sizeof(sfm_r2r_transform) * (size_t)k);
                memcpy(w.bscore, w.score, sizeof(double) * (size_t)k);
            }
            if (best_all <= EXACT_FIT)
                kept = SUBSETS; /* the data are met exactly: no subset can do better */
        }
    }
    if (kept) {
        double limit = GATE_FACTOR * best_all + 1e-9;
        memcpy(w.cand, w.bcand, sizeof(sfm_r2r_transform) * (size_t)nbest);
        memcpy(w.score, w.bscore, sizeof(double) * (size_t)nbest);
        return emit(&w, nbest, limit < GATE_TOL ? limit : GATE_TOL, out);
    }
    if (solved)
        return 0;
    if (singular)
        return SFM_E_DEGENERATE;
    return other ? other : SFM_E_UNSUPPORTED;
}

SFM_API int sfm_r2r_solve(const sfm_r2r_step *steps, int n_steps,
                          sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS], void *ws, size_t ws_size)
{
    return sfmi_r2r_solve_with(sfmi_r2r_table, steps, n_steps, out, ws, ws_size);
}
