/*
 * The robot-to-robot dispatcher (sfm_r2r_predict, sfm_r2r_classify,
 * sfm_r2r_solve) against scenes built from world geometry: both robots get
 * world orientations and positions at every step; ego-motions, the truth
 * (C, p) and the measurements are derived from those, never from the
 * library's formulas.
 *
 * The reduction is checked without the base-system solvers: the truth
 * mapped into the canonical frames must satisfy the canonical steps, and an
 * oracle registry (each "solver" knows the world truth and finds the
 * canonical frame by trying every re-referencing and exchange, then adds
 * decoys) drives sfm_r2r_solve end to end. The solvers present on this
 * build are run on every combination too; absent ones are skipped, with a
 * line saying so.
 */
#include <math.h>
#include <string.h>

#include "r2r_api_scene.h"
#include "sfm/sfm_r2r.h"
#include "sfm_test.h"
#include "solvers/r2r_solve_internal.h"

/* ---- An oracle registry ---------------------------------------------------- */

static sfm_r2r_transform oracle_truth;
static const sfm_r2r_step *oracle_steps;
static int oracle_n, oracle_calls, oracle_singular;

/* Canonical truth if the dispatcher re-referenced to step j (exchanged or
 * not): the maps written out from the conventions. */
static void oracle_map(int j, int swap, sfm_r2r_transform *o)
{
    const sfm_r2r_step *s = oracle_steps + j;
    double Cs[9], ps[3], q[3], M[9];
    const double *R1 = swap ? s->R2.m : s->R1.m, *t1 = swap ? s->t2.v : s->t1.v;
    const double *R2 = swap ? s->R1.m : s->R2.m, *t2 = swap ? s->t1.v : s->t2.v;
    if (swap) {
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                Cs[3 * r + c] = oracle_truth.C.m[3 * c + r];
        mvec(Cs, oracle_truth.p.v, ps);
        for (int i = 0; i < 3; i++)
            ps[i] = -ps[i];
    } else {
        memcpy(Cs, oracle_truth.C.m, sizeof Cs);
        memcpy(ps, oracle_truth.p.v, sizeof ps);
    }
    tmul(R1, Cs, M);
    mul(M, R2, o->C.m);
    mvec(Cs, t2, q);
    for (int i = 0; i < 3; i++)
        q[i] += ps[i] - t1[i];
    tmv(R1, q, o->p.v);
}

static int oracle_solve(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws, int n)
{
    (void)ws;
    oracle_calls++;
    if (oracle_singular)
        return SFM_E_SINGULAR;
    if (!(steps[0].R1.m[0] == 1.0 && steps[0].R1.m[4] == 1.0 && steps[0].R2.m[8] == 1.0 &&
          steps[0].t1.v[0] == 0.0 && steps[0].t2.v[2] == 0.0))
        return 0; /* the canonical first step must be the identity */
    for (int j = 0; j < oracle_n; j++)
        for (int swap = 0; swap < 2; swap++) {
            sfm_r2r_transform c;
            oracle_map(j, swap, &c);
            double e = 0.0;
            for (int i = 0; i < n; i++)
                e = fmax(e, step_residual(steps + i, &c));
            if (e < 1e-9) {
                /* two decoys around the truth, then the truth */
                out[0] = c;
                out[1] = c;
                out[0].p.v[0] += 0.3;
                out[1].C.m[0] = -out[1].C.m[0];
                out[1].C.m[1] = -out[1].C.m[1];
                out[1].C.m[2] = -out[1].C.m[2];
                out[2] = c;
                return 3;
            }
        }
    return 0;
}

#define ORACLE(name, sys, n)                                                                     \
    static int oracle_##name(const sfm_r2r_step *s, sfm_r2r_transform *o, double *ws)           \
    {                                                                                            \
        return oracle_solve(s, o, ws, n);                                                        \
    }                                                                                            \
    static const sfmi_r2r_system_desc odesc_##name = {sys, n, {0}, 3, 4, oracle_##name, #name}
ORACLE(s1, 1, 2);
ORACLE(s2, 2, 2);
ORACLE(s3, 3, 3);
ORACLE(s4, 4, 2);
ORACLE(s5, 5, 2);
ORACLE(s6, 6, 3);
ORACLE(s7, 7, 3);
ORACLE(s8, 8, 4);
ORACLE(s9, 9, 3);
ORACLE(s10, 10, 3);
ORACLE(s11, 11, 4);
ORACLE(s12, 12, 4);
ORACLE(s13, 13, 5);
ORACLE(s14, 14, 6);
static const sfmi_r2r_system_desc *const oracle_table[SFM_R2R_SYS_COUNT_] = {
    NULL, &odesc_s1, &odesc_s2, &odesc_s3, &odesc_s4, &odesc_s5, &odesc_s6, &odesc_s7,
    &odesc_s8, &odesc_s9, &odesc_s10, &odesc_s11, &odesc_s12, &odesc_s13, &odesc_s14};

static void oracle_set(const scene *sc)
{
    oracle_truth = sc->T;
    oracle_steps = sc->s;
    oracle_n = sc->n;
    oracle_singular = 0;
}

static double ws_buf[4096];

/* ---- Tests ------------------------------------------------------------------ */

SFM_TEST(r2r_predict_matches_world_geometry)
{
    static scene sc;
    unsigned has[MAXS];
    for (int k = 0; k < MAXS; k++)
        has[k] = 7;
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        make_scene(t, &sc, 6, has);
        for (int k = 0; k < 6; k++)
            worst = fmax(worst, step_residual(sc.s + k, &sc.T));
    }
    SFM_CHECK_MSG(worst < 1e-12, "predicted vs world measurements: %g", worst);
}

SFM_TEST(r2r_predict_bad_inputs)
{
    static scene sc;
    unsigned has[1] = {7};
    make_scene(t, &sc, 1, has);
    double d = -1.0;
    sfm_vec3 b1 = {{9, 9, 9}}, b2 = {{9, 9, 9}};
    SFM_CHECK_EQ_INT(sfm_r2r_predict(NULL, &sc.T, &d, &b1, &b2), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_predict(sc.s, NULL, &d, &b1, &b2), SFM_E_ARGUMENT);
    sfm_r2r_transform bad = sc.T;
    bad.p.v[1] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_r2r_predict(sc.s, &bad, &d, &b1, &b2), SFM_E_NONFINITE);
    sfm_r2r_step st = sc.s[0];
    st.t2.v[0] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_r2r_predict(&st, &sc.T, &d, &b1, &b2), SFM_E_NONFINITE);
    /* robots at one place: a distance of zero, no bearing */
    st = sc.s[0];
    bad = sc.T;
    for (int i = 0; i < 3; i++)
        st.t1.v[i] = bad.C.m[3 * i] * st.t2.v[0] + bad.C.m[3 * i + 1] * st.t2.v[1] +
                     bad.C.m[3 * i + 2] * st.t2.v[2] + bad.p.v[i];
    SFM_CHECK_EQ_INT(sfm_r2r_predict(&st, &bad, &d, &b1, NULL), SFM_E_SINGULAR);
    SFM_CHECK(d == -1.0 && b1.v[0] == 9.0 && b2.v[0] == 9.0);
    SFM_CHECK_EQ_INT(sfm_r2r_predict(&st, &bad, &d, NULL, NULL), SFM_OK);
    SFM_CHECK(d < 1e-12);
}

SFM_TEST(r2r_classify_every_combination)
{
    static scene sc;
    int total = n_combos(), bad_partition = 0, wrong = 0, per[SFM_R2R_SYS_COUNT_] = {0};
    for (int i = 0; i < total; i++) {
        unsigned m[6];
        combo(i, m);
        int matches, want = expected_class(m, 6, &matches);
        bad_partition += matches != 1;
        make_scene(t, &sc, 6, m);
        int got = sfm_r2r_classify(sc.s, 6);
        if (got != want)
            wrong++;
        else
            per[got]++;
    }
    SFM_TEST_LOG("%d six-equation combinations over six steps", total);
    SFM_CHECK_EQ_INT(bad_partition, 0);
    SFM_CHECK_EQ_INT(wrong, 0);
    for (int s = 1; s < SFM_R2R_SYS_COUNT_; s++)
        SFM_CHECK_MSG(per[s] > 0, "no combination classified as %s", sys_names[s]);
}

SFM_TEST(r2r_classify_bad_inputs)
{
    static scene sc;
    unsigned has[4] = {D_ | B1_, D_, D_, D_};
    make_scene(t, &sc, 4, has);
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 4), SFM_R2R_SYS_DB1_D_D_D);
    SFM_CHECK_EQ_INT(sfm_r2r_classify(NULL, 4), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 0), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 3), SFM_E_ARGUMENT); /* five equations */
    sc.s[3].has = D_ | B2_;
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 4), SFM_E_ARGUMENT); /* eight */
    sc.s[3].has = D_;
    sc.s[2].d = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 4), SFM_E_NONFINITE);
    sc.s[2].d = -1.0;
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 4), SFM_E_ARGUMENT);
    sc.s[2].d = 1.0;
    /* the same distance twice where both robots stand: five equations */
    sc.s[2].t1 = sc.s[1].t1;
    sc.s[2].t2 = sc.s[1].t2;
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 4), SFM_E_DEGENERATE);
}

SFM_TEST(r2r_canonical_frames_hold_the_truth)
{
    static scene sc;
    int total = n_combos(), stride = SFM_TEST_ITERS(10) == 10 ? 1 : 10, checked = 0;
    double worst = 0.0, worst_back = 0.0;
    int bad_pattern = 0, bad_ident = 0;
    for (int i = 0; i < total; i += stride) {
        unsigned m[6];
        combo(i, m);
        make_scene(t, &sc, 6, m);
        sfmi_r2r_canon c;
        int sys = sfmi_r2r_canonicalize(sc.s, m, 6, &c);
        SFM_CHECK_EQ_INT(sys, sfm_r2r_classify(sc.s, 6));
        if (sys < 1)
            continue;
        unsigned pm[6];
        int pn = parse_name(sys_names[sys], pm);
        bad_pattern += pn != c.n;
        for (int k = 0; k < c.n && k < pn; k++)
            bad_pattern += c.steps[k].has != pm[k];
        for (int r = 0; r < 9; r++)
            bad_ident += c.steps[0].R1.m[r] != (r % 4 == 0 ? 1.0 : 0.0) ||
                         c.steps[0].R2.m[r] != (r % 4 == 0 ? 1.0 : 0.0);
        bad_ident += nrm(c.steps[0].t1.v) != 0.0 || nrm(c.steps[0].t2.v) != 0.0;
        sfm_r2r_transform Tc, Tb;
        sfmi_r2r_to_canonical(&c, &sc.T, &Tc);
        for (int k = 0; k < c.n; k++) {
            worst = fmax(worst, step_residual(c.steps + k, &Tc));
            if (c.steps[k].has & B1_)
                worst = fmax(worst, fabs(nrm(c.steps[k].b1.v) - 1.0));
        }
        sfmi_r2r_from_canonical(&c, &Tc, &Tb);
        worst_back = fmax(worst_back, terr(&Tb, &sc.T));
        checked++;
    }
    SFM_TEST_LOG("%d combinations: canonical residual of the truth %.2g, round trip %.2g", checked,
                 worst, worst_back);
    SFM_CHECK_EQ_INT(bad_pattern, 0);
    SFM_CHECK_EQ_INT(bad_ident, 0);
    SFM_CHECK(worst < 1e-10);
    SFM_CHECK(worst_back < 1e-12);
}

SFM_TEST(r2r_registry_matches_the_patterns)
{
    for (int s = 1; s < SFM_R2R_SYS_COUNT_; s++) {
        const sfmi_r2r_system_desc *d = sfmi_r2r_table[s];
        SFM_CHECK(d != NULL);
        if (!d)
            continue;
        unsigned pm[6];
        int pn = parse_name(sys_names[s], pm);
        SFM_CHECK_EQ_INT(d->id, s);
        SFM_CHECK_EQ_INT(d->n_steps, pn);
        for (int k = 0; k < pn; k++)
            SFM_CHECK_MSG(d->pattern[k] == pm[k], "%s step %d", sys_names[s], k);
        SFM_CHECK(d->solve != NULL);
    }
}

SFM_TEST(r2r_solve_oracle_every_combination)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    int total = n_combos(), stride = SFM_TEST_ITERS(10) == 10 ? 1 : 10, ok = 0, runs = 0;
    size_t wsz = sfmi_r2r_solve_ws_size_with(oracle_table, 6);
    SFM_CHECK(wsz <= sizeof ws_buf);
    for (int i = 0; i < total; i += stride) {
        unsigned m[6];
        combo(i, m);
        make_scene(t, &sc, 6, m);
        oracle_set(&sc);
        int n = sfmi_r2r_solve_with(oracle_table, sc.s, 6, out, ws_buf, wsz);
        runs++;
        /* the decoys fail the six equations: only the truth comes back;
         * {d,b1} {d,b1} has robot 2 at two positions (on a line) and no b2 */
        if (sfm_r2r_classify(sc.s, 6) == SFM_R2R_SYS_DB1_DB1)
            ok += n == SFM_E_DEGENERATE;
        else if (n == 1 && terr(out, &sc.T) < 1e-9)
            ok++;
    }
    SFM_TEST_LOG("truth alone returned in %d of %d", ok, runs);
    SFM_CHECK_EQ_INT(ok, runs);
}

SFM_TEST(r2r_solve_oracle_long_sequences)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    unsigned has[MAXS];
    int ok = 0, runs = 0, calls = 0;
    for (int it = 0; it < SFM_TEST_ITERS(300); it++) {
        int n = 7 + (int)(sfm_rng_uniform(&t->rng) * 14.0); /* 7..20 */
        if (n > MAXS)
            n = MAXS;
        int all = it % 2 == 0;
        for (int k = 0; k < n; k++)
            has[k] = all ? 7u : 1u + (unsigned)(sfm_rng_uniform(&t->rng) * 7.0) % 7u;
        make_scene(t, &sc, n, has);
        oracle_set(&sc);
        oracle_calls = 0;
        size_t wsz = sfmi_r2r_solve_ws_size_with(oracle_table, n);
        int r = sfmi_r2r_solve_with(oracle_table, sc.s, n, out, ws_buf, wsz);
        runs++;
        calls += oracle_calls;
        if (r == 1 && terr(out, &sc.T) < 1e-9)
            ok++;
    }
    SFM_TEST_LOG("7-20 steps: truth alone in %d of %d (%.2f subsets solved per call)", ok, runs,
                 (double)calls / runs);
    SFM_CHECK_EQ_INT(ok, runs);
}

/* A registry where only some systems are built: the subset search must
 * reach them. */
SFM_TEST(r2r_solve_oracle_partial_registry)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    static const sfmi_r2r_system_desc pend = {SFM_R2R_SYS_NONE, 0, {0}, 0, 0, NULL, "absent"};
    const sfmi_r2r_system_desc *tab[SFM_R2R_SYS_COUNT_];
    unsigned has[MAXS];
    int ok = 0, runs = 0;
    for (int only = 1; only < SFM_R2R_SYS_COUNT_; only++) {
        for (int s = 0; s < SFM_R2R_SYS_COUNT_; s++)
            tab[s] = s == only ? oracle_table[s] : &pend;
        for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
            int n = 8 + it % 5;
            for (int k = 0; k < n; k++)
                has[k] = 7u;
            make_scene(t, &sc, n, has);
            oracle_set(&sc);
            int r = sfmi_r2r_solve_with(tab, sc.s, n, out, ws_buf, sizeof ws_buf);
            runs++;
            if (only == SFM_R2R_SYS_DB1_DB1) /* every subset of it is degenerate */
                ok += r == SFM_E_UNSUPPORTED;
            else if (r == 1 && terr(out, &sc.T) < 1e-9)
                ok++;
            else
                SFM_TEST_LOG("only %s present: %d", sys_names[only], r);
        }
    }
    SFM_CHECK_EQ_INT(ok, runs);
    /* nothing present: unsupported, not zero solutions */
    for (int s = 0; s < SFM_R2R_SYS_COUNT_; s++)
        tab[s] = &pend;
    SFM_CHECK_EQ_INT(sfmi_r2r_solve_with(tab, sc.s, sc.n, out, ws_buf, sizeof ws_buf), SFM_E_UNSUPPORTED);
}

SFM_TEST(r2r_solve_bad_inputs_write_nothing)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    unsigned has[4] = {D_ | B1_, D_, D_, D_};
    make_scene(t, &sc, 4, has);
    size_t wsz = sfm_r2r_solve_workspace_size(4);
    SFM_CHECK(wsz > 0 && wsz <= sizeof ws_buf);
    SFM_CHECK_EQ_INT(sfm_r2r_solve_workspace_size(0), 0);
    SFM_CHECK(sfm_r2r_solve_workspace_size(20) > wsz);
    sfm_test_fill_canary(out, sizeof out);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(NULL, 4, out, ws_buf, wsz), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 0, out, ws_buf, wsz), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, NULL, ws_buf, wsz), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, NULL, wsz), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 3, out, ws_buf, wsz), SFM_E_ARGUMENT); /* five equations */
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz - 1), SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, 0), SFM_E_WORKSPACE);
    sfm_r2r_step keep = sc.s[1];
    sc.s[1].d = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_NONFINITE);
    sc.s[1] = keep;
    sc.s[1].R2.m[4] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_NONFINITE);
    sc.s[1] = keep;
    sc.s[1].d = -2.0;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_ARGUMENT);
    sc.s[1].d = 0.0;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_ARGUMENT);
    sc.s[1] = keep;
    keep = sc.s[0];
    sc.s[0].b1.v[0] = sc.s[0].b1.v[1] = sc.s[0].b1.v[2] = 0.0;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_ARGUMENT);
    sc.s[0] = keep;
    sc.s[0].has |= 8u;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_ARGUMENT);
    sc.s[0] = keep;
    sc.s[2].R1.m[0] *= 1.01; /* not a rotation */
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_ARGUMENT);
    sc.s[2].R1.m[0] /= 1.01;
    for (int i = 0; i < 9; i++) /* a reflection */
        sc.s[2].R2.m[i] = -sc.s[2].R2.m[i];
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, wsz), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
}

SFM_TEST(r2r_solve_degenerate_motion)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    unsigned has[MAXS];
    sfm_test_fill_canary(out, sizeof out);

    /* both robots standing still, turning: three bearings of one vector */
    for (int k = 0; k < 3; k++)
        has[k] = B1_;
    make_scene(t, &sc, 3, has);
    for (int k = 1; k < 3; k++) {
        memcpy(sc.P1[k], sc.P1[0], sizeof sc.P1[0]);
        memcpy(sc.P2[k], sc.P2[0], sizeof sc.P2[0]);
    }
    derive(&sc, has);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 3, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);
    SFM_CHECK_EQ_INT(sfm_r2r_classify(sc.s, 3), SFM_E_DEGENERATE);

    /* standing still over twelve steps with every measurement */
    for (int k = 0; k < 12; k++)
        has[k] = 7u;
    make_scene(t, &sc, 12, has);
    for (int k = 1; k < 12; k++) {
        memcpy(sc.P1[k], sc.P1[0], sizeof sc.P1[0]);
        memcpy(sc.P2[k], sc.P2[0], sizeof sc.P2[0]);
    }
    derive(&sc, has);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 12, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);

    /* six distances, both robots on parallel straight lines */
    for (int k = 0; k < 6; k++)
        has[k] = D_;
    make_scene(t, &sc, 6, has);
    double u[3];
    sfm_test_random_unit(t, u);
    for (int k = 1; k < 6; k++)
        for (int i = 0; i < 3; i++) {
            sc.P1[k][i] = sc.P1[0][i] + 0.7 * k * u[i];
            sc.P2[k][i] = sc.P2[0][i] + (0.3 + 0.2 * k * k) * u[i];
        }
    derive(&sc, has);
    oracle_set(&sc);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 6, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);
    SFM_CHECK_EQ_INT(sfmi_r2r_solve_with(oracle_table, sc.s, 6, out, ws_buf, sizeof ws_buf),
                     SFM_E_DEGENERATE);

    /* six distances, only robot 2 on a line (robot 1 anywhere) */
    make_scene(t, &sc, 6, has);
    for (int k = 1; k < 6; k++)
        for (int i = 0; i < 3; i++)
            sc.P2[k][i] = sc.P2[0][i] + (0.5 * k - 1.2) * u[i];
    derive(&sc, has);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 6, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);

    /* twenty distances on parallel lines */
    for (int k = 0; k < 20; k++)
        has[k] = D_;
    make_scene(t, &sc, 20, has);
    for (int k = 1; k < 20; k++)
        for (int i = 0; i < 3; i++) {
            sc.P1[k][i] = sc.P1[0][i] + 0.2 * k * u[i];
            sc.P2[k][i] = sc.P2[0][i] - 0.1 * k * u[i];
        }
    derive(&sc, has);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 20, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);

    /* a template singular for these data */
    for (int k = 0; k < 4; k++)
        has[k] = k ? D_ : D_ | B1_;
    make_scene(t, &sc, 4, has);
    oracle_set(&sc);
    oracle_singular = 1;
    SFM_CHECK_EQ_INT(sfmi_r2r_solve_with(oracle_table, sc.s, 4, out, ws_buf, sizeof ws_buf),
                     SFM_E_DEGENERATE);
    oracle_singular = 0;
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));

    /* control: the same six distances with general motion are answered */
    for (int k = 0; k < 6; k++)
        has[k] = D_;
    make_scene(t, &sc, 6, has);
    oracle_set(&sc);
    SFM_CHECK_EQ_INT(sfmi_r2r_solve_with(oracle_table, sc.s, 6, out, ws_buf, sizeof ws_buf), 1);
}

/* The base-system solvers of this build on every combination; all 14 are
 * built, so none may answer SFM_E_UNSUPPORTED (a registry entry lost would
 * be named in the log). Systems
 * whose six equations have rank five (descriptor max_solutions 0, e.g.
 * DB1_DB1) must say SFM_E_DEGENERATE every time. */
SFM_TEST(r2r_solve_present_systems_every_combination)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    int total = n_combos(), stride = SFM_TEST_ITERS(10) == 10 ? 1 : 10;
    int runs[SFM_R2R_SYS_COUNT_] = {0}, found[SFM_R2R_SYS_COUNT_] = {0};
    int absent[SFM_R2R_SYS_COUNT_] = {0}, degen[SFM_R2R_SYS_COUNT_] = {0}, skipped = 0;
    size_t wsz = sfm_r2r_solve_workspace_size(6);
    SFM_CHECK(wsz <= sizeof ws_buf);
    for (int i = 0; i < total; i += stride) {
        unsigned m[6];
        combo(i, m);
        make_scene(t, &sc, 6, m);
        int sys = sfm_r2r_classify(sc.s, 6);
        SFM_CHECK(sys >= 1);
        if (sys < 1)
            continue;
        int n = sfm_r2r_solve(sc.s, 6, out, ws_buf, wsz);
        if (n == SFM_E_UNSUPPORTED) {
            absent[sys] = 1;
            skipped++;
            continue;
        }
        runs[sys]++;
        if (sfmi_r2r_table[sys]->max_solutions == 0) {
            degen[sys] += n == SFM_E_DEGENERATE;
            continue;
        }
        for (int j = 0; j < n; j++)
            if (terr(out + j, &sc.T) < 1e-6) {
                found[sys]++;
                break;
            }
    }
    char names[256] = "";
    for (int s = 1; s < SFM_R2R_SYS_COUNT_; s++) {
        if (absent[s]) {
            strcat(names, " ");
            strcat(names, sys_names[s]);
            continue;
        }
        if (runs[s] == 0) { /* reduced runs sample every tenth combination */
            SFM_TEST_LOG("%s: no combination sampled", sys_names[s]);
            continue;
        }
        if (sfmi_r2r_table[s]->max_solutions == 0) {
            SFM_TEST_LOG("%s: rank-deficient, SFM_E_DEGENERATE in %d of %d", sys_names[s], degen[s], runs[s]);
            SFM_CHECK_EQ_INT(degen[s], runs[s]);
            continue;
        }
        SFM_TEST_LOG("%s: truth among the solutions in %d of %d", sys_names[s], found[s], runs[s]);
        SFM_CHECK_MSG(found[s] * 1000 >= runs[s] * 990, "%s: %d of %d", sys_names[s], found[s], runs[s]);
    }
    if (skipped)
        SFM_TEST_LOG("%d combinations of systems not on this build:%s", skipped, names);
    SFM_CHECK_EQ_INT(skipped, 0);
}

/* 7-20 steps through the solvers of this build: all measurements, or a
 * random subset at each step; the truth must come back first. */
SFM_TEST(r2r_solve_present_long_sequences)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    unsigned has[MAXS];
    int ok = 0, runs = 0, unsupported = 0, zero = 0, other = 0;
    for (int it = 0; it < SFM_TEST_ITERS(500); it++) {
        int n = 7 + (int)(sfm_rng_uniform(&t->rng) * 14.0);
        if (n > MAXS)
            n = MAXS;
        int all = it % 2 == 0;
        for (int k = 0; k < n; k++)
            has[k] = all ? 7u : 1u + (unsigned)(sfm_rng_uniform(&t->rng) * 7.0) % 7u;
        make_scene(t, &sc, n, has);
        int r = sfm_r2r_solve(sc.s, n, out, ws_buf, sfm_r2r_solve_workspace_size(n));
        if (r == SFM_E_UNSUPPORTED) {
            unsupported++;
            continue;
        }
        runs++;
        if (r >= 1 && terr(out, &sc.T) < 1e-6)
            ok++;
        else if (r == 0)
            zero++;
        else if (r < 0 || r > 1)
            other++;
    }
    SFM_TEST_LOG("7-20 steps: truth first in %d of %d (%d none kept, %d other), %d unsupported", ok,
                 runs, zero, other, unsupported);
    SFM_CHECK(ok * 1000 >= runs * 990);
    SFM_CHECK_EQ_INT(unsupported, 0);
}

/* Noisy 7-20 step sequences (1 mm on distances, 0.5 mrad on bearings):
 * the first answer stays near the truth; the minimal subset's answer is
 * the start of a refinement, so the bound is loose. */
SFM_TEST(r2r_solve_present_noisy_sequences)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    unsigned has[MAXS];
    int runs = 0, near = 0;
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        int n = 7 + (int)(sfm_rng_uniform(&t->rng) * 14.0);
        if (n > MAXS)
            n = MAXS;
        for (int k = 0; k < n; k++)
            has[k] = it % 2 ? 1u + (unsigned)(sfm_rng_uniform(&t->rng) * 7.0) % 7u : 7u;
        make_scene(t, &sc, n, has);
        for (int k = 0; k < n; k++) {
            sc.s[k].d += sfm_test_normal(t, 1e-3);
            for (int i = 0; i < 3; i++) {
                sc.s[k].b1.v[i] += sfm_test_normal(t, 5e-4);
                sc.s[k].b2.v[i] += sfm_test_normal(t, 5e-4);
            }
        }
        int r = sfm_r2r_solve(sc.s, n, out, ws_buf, sfm_r2r_solve_workspace_size(n));
        SFM_CHECK(r != SFM_E_UNSUPPORTED);
        runs++;
        if (r >= 1) {
            double e = terr(out, &sc.T);
            worst = fmax(worst, e);
            near += e < 0.05;
        }
    }
    SFM_TEST_LOG("noisy 7-20 steps: first answer within 0.05 of the truth in %d of %d, worst %.3g", near,
                 runs, worst);
    SFM_CHECK(near * 100 >= runs * 99);
}

/* The line rule with bearings: robot 2 on a line (or still) and no b2 lets
 * C turn about that line unseen; likewise robot 1 and b1. */
SFM_TEST(r2r_solve_line_rule_with_bearings)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    unsigned has[MAXS];
    double u[3];
    sfm_test_fill_canary(out, sizeof out);
    /* DB1_D_D_D, robot 2 on a line */
    for (int k = 0; k < 4; k++)
        has[k] = k ? D_ : D_ | B1_;
    make_scene(t, &sc, 4, has);
    sfm_test_random_unit(t, u);
    for (int k = 1; k < 4; k++)
        for (int i = 0; i < 3; i++)
            sc.P2[k][i] = sc.P2[0][i] + (0.8 * k - 1.5) * u[i];
    derive(&sc, has);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 4, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);
    /* the same data exchanged: robot 1 on the line, b2 only */
    sfm_r2r_step sw[4];
    for (int k = 0; k < 4; k++) {
        sw[k] = sc.s[k];
        sw[k].R1 = sc.s[k].R2;
        sw[k].t1 = sc.s[k].t2;
        sw[k].R2 = sc.s[k].R1;
        sw[k].t2 = sc.s[k].t1;
        sw[k].b2 = sc.s[k].b1;
        sw[k].has = sc.s[k].has & B1_ ? D_ | B2_ : D_;
    }
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sw, 4, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);
    /* three bearings from robot 1 while robot 2 stands still */
    for (int k = 0; k < 3; k++)
        has[k] = B1_;
    make_scene(t, &sc, 3, has);
    for (int k = 1; k < 3; k++)
        memcpy(sc.P2[k], sc.P2[0], sizeof sc.P2[0]);
    derive(&sc, has);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 3, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);
    /* 15 steps of d and b1, robot 2 on a line */
    for (int k = 0; k < 15; k++)
        has[k] = D_ | B1_;
    make_scene(t, &sc, 15, has);
    for (int k = 1; k < 15; k++)
        for (int i = 0; i < 3; i++)
            sc.P2[k][i] = sc.P2[0][i] + 0.3 * k * u[i];
    derive(&sc, has);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(sc.s, 15, out, ws_buf, sizeof ws_buf), SFM_E_DEGENERATE);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    /* control: add b2 at every step and the turn is seen */
    for (int k = 0; k < 15; k++)
        has[k] = 7u;
    derive(&sc, has);
    oracle_set(&sc);
    int r = sfmi_r2r_solve_with(oracle_table, sc.s, 15, out, ws_buf, sizeof ws_buf);
    SFM_CHECK_EQ_INT(r, 1);
    SFM_CHECK(r == 1 && terr(out, &sc.T) < 1e-9);
}
