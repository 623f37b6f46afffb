/*
 * Scenes for the robot-to-robot dispatcher tests (tests/unit/test_r2r_api.c,
 * tests/native/test_r2r_api_long.c): both robots get world orientations and
 * positions at every step; ego-motions, the truth (C, p) and the
 * measurements are derived from those, never from the library's formulas.
 * Also the 14 patterns by name and every six-equation combination of
 * has-masks over six steps.
 */
#ifndef TESTS_R2R_API_SCENE_H
#define TESTS_R2R_API_SCENE_H

#include <math.h>
#include <string.h>

#include "sfm/sfm_r2r.h"
#include "sfm_test.h"

#define MAXS 20
#define D_ SFM_R2R_D
#define B1_ SFM_R2R_B1
#define B2_ SFM_R2R_B2

typedef struct scene {
    int n;
    double W1[MAXS][9], P1[MAXS][3], W2[MAXS][9], P2[MAXS][3]; /* body-to-world */
    sfm_r2r_transform T;
    sfm_r2r_step s[MAXS];
} scene;

static inline void mul(const double *A, const double *B, double *C)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

static inline void tmul(const double *A, const double *B, double *C) /* A^T B */
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c];
}

static inline void tmv(const double *A, const double *x, double *y) /* A^T x */
{
    for (int c = 0; c < 3; c++)
        y[c] = A[c] * x[0] + A[3 + c] * x[1] + A[6 + c] * x[2];
}

static inline void mvec(const double *A, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = A[3 * r] * x[0] + A[3 * r + 1] * x[1] + A[3 * r + 2] * x[2];
}

static inline double nrm(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* Ego-motions, truth and measurements from the world poses in sc. */
static inline void derive(scene *sc, const unsigned *has)
{
    tmul(sc->W1[0], sc->W2[0], sc->T.C.m);
    double d0[3] = {sc->P2[0][0] - sc->P1[0][0], sc->P2[0][1] - sc->P1[0][1], sc->P2[0][2] - sc->P1[0][2]};
    tmv(sc->W1[0], d0, sc->T.p.v);
    for (int k = 0; k < sc->n; k++) {
        sfm_r2r_step *s = sc->s + k;
        memset(s, 0, sizeof *s);
        double a[3], b[3], v[3];
        tmul(sc->W1[0], sc->W1[k], s->R1.m);
        tmul(sc->W2[0], sc->W2[k], s->R2.m);
        for (int i = 0; i < 3; i++) {
            a[i] = sc->P1[k][i] - sc->P1[0][i];
            b[i] = sc->P2[k][i] - sc->P2[0][i];
            v[i] = sc->P2[k][i] - sc->P1[k][i];
        }
        tmv(sc->W1[0], a, s->t1.v);
        tmv(sc->W2[0], b, s->t2.v);
        double d = nrm(v);
        s->has = has[k];
        s->d = d;
        tmv(sc->W1[k], v, s->b1.v);
        tmv(sc->W2[k], v, s->b2.v);
        for (int i = 0; i < 3; i++) {
            s->b1.v[i] /= d;
            s->b2.v[i] /= -d;
        }
    }
}

/* Random poses a few metres apart (robots at least 0.5 m from each other). */
static inline void make_scene(sfm_test_ctx *t, scene *sc, int n, const unsigned *has)
{
    sc->n = n;
    for (int k = 0; k < n; k++) {
        sfm_test_random_rotation(t, sc->W1[k]);
        sfm_test_random_rotation(t, sc->W2[k]);
        double dd;
        do {
            for (int i = 0; i < 3; i++) {
                sc->P1[k][i] = sfm_test_uniform(t, -3.0, 3.0);
                sc->P2[k][i] = sfm_test_uniform(t, -3.0, 3.0);
            }
            double v[3] = {sc->P2[k][0] - sc->P1[k][0], sc->P2[k][1] - sc->P1[k][1], sc->P2[k][2] - sc->P1[k][2]};
            dd = nrm(v);
        } while (dd < 0.5);
    }
    derive(sc, has);
}

static inline double terr(const sfm_r2r_transform *a, const sfm_r2r_transform *b)
{
    double e = 0.0;
    for (int i = 0; i < 9; i++)
        e = fmax(e, fabs(a->C.m[i] - b->C.m[i]));
    for (int i = 0; i < 3; i++)
        e = fmax(e, fabs(a->p.v[i] - b->p.v[i]));
    return e;
}

/* max deviation of the predicted measurements from a step's own */
static inline double step_residual(const sfm_r2r_step *s, const sfm_r2r_transform *T)
{
    double d;
    sfm_vec3 b1, b2;
    if (sfm_r2r_predict(s, T, &d, &b1, &b2) != SFM_OK)
        return HUGE_VAL;
    double e = 0.0;
    if (s->has & D_)
        e = fmax(e, fabs(d - s->d));
    for (int i = 0; i < 3; i++) {
        if (s->has & B1_)
            e = fmax(e, fabs(b1.v[i] - s->b1.v[i] / nrm(s->b1.v)));
        if (s->has & B2_)
            e = fmax(e, fabs(b2.v[i] - s->b2.v[i] / nrm(s->b2.v)));
    }
    return e;
}

/* ---- The 14 patterns as the header names them, and every combination ---- */

static const char *const sys_names[SFM_R2R_SYS_COUNT_] = {
    "", "DB1B2_D", "B1B2_B1", "B1B2_D_D", "DB1_DB1", "DB1_DB2", "DB1_B1_D", "DB1_B2_D",
    "DB1_D_D_D", "B1_B1_B1", "B1_B1_B2", "B1_B1_D_D", "B1_B2_D_D", "B1_D_D_D_D", "D6"};

/* Parses "DB1_B2_D" into masks; returns the step count. */
static inline int parse_name(const char *nm, unsigned *m)
{
    int n = 0;
    if (!strcmp(nm, "D6")) { /* six distances */
        for (int k = 0; k < 6; k++)
            m[k] = D_;
        return 6;
    }
    m[0] = 0;
    for (const char *c = nm; *c; c++) {
        if (*c == '_') {
            m[++n] = 0;
        } else if (*c == 'D') {
            m[n] |= D_;
        } else if (*c == 'B') {
            m[n] |= c[1] == '1' ? B1_ : B2_;
            c++;
        }
    }
    return n + 1;
}

static inline int eqs(unsigned m) { return (m & 1u) + ((m & 2u) ? 2 : 0) + ((m & 4u) ? 2 : 0); }

/* Histogram of the measured masks: the orbit key under reordering. */
static inline void histogram(const unsigned *m, int n, int swap, int h[8])
{
    memset(h, 0, 8 * sizeof(int));
    for (int i = 0; i < n; i++) {
        unsigned x = m[i];
        if (swap)
            x = (x & 1u) | ((x & 2u) << 1) | ((x & 4u) >> 1);
        if (x)
            h[x]++;
    }
}

/* The class of a six-equation sequence by definition: the named pattern
 * whose histogram equals the sequence's, robots as given or exchanged.
 * Writes how many patterns matched (1 for a partition). */
static inline int expected_class(const unsigned *m, int n, int *matches)
{
    int hs[8], found = 0;
    *matches = 0;
    histogram(m, n, 0, hs);
    for (int s = 1; s < SFM_R2R_SYS_COUNT_; s++) {
        unsigned pm[6];
        int pn = parse_name(sys_names[s], pm), h0[8], h1[8];
        histogram(pm, pn, 0, h0);
        histogram(pm, pn, 1, h1);
        if (!memcmp(hs, h0, sizeof hs) || !memcmp(hs, h1, sizeof hs)) {
            (*matches)++;
            found = s;
        }
    }
    return found;
}

/* Every has-mask sequence over six steps (steps may be empty) carrying six
 * equations, in a fixed order (1391 of them), packed three bits per step. */
#define MAX_COMBOS 1400
static int combo_list[MAX_COMBOS], combo_count = -1;

static inline int n_combos(void)
{
    if (combo_count < 0) {
        combo_count = 0;
        for (int code = 0; code < 8 * 8 * 8 * 8 * 8 * 8; code++) {
            int e = 0, c = code;
            for (int k = 0; k < 6; k++, c >>= 3)
                e += eqs((unsigned)(c & 7));
            if (e == 6 && combo_count < MAX_COMBOS)
                combo_list[combo_count++] = code;
        }
    }
    return combo_count;
}

static inline void combo(int i, unsigned m[6])
{
    int c = combo_list[i];
    for (int k = 0; k < 6; k++, c >>= 3)
        m[k] = (unsigned)(c & 7);
}

#endif
