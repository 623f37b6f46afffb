/*
 * Synthetic robot-to-robot sequences with a known answer, built from the
 * measurement model of sfm_r2r.h written out here independently of the
 * library: w = C t2 + p - t1, d = |w|, b1 = R1^T w / d, b2 = -R2^T C^T w / d.
 */
#ifndef TESTS_R2R_SCENE_H
#define TESTS_R2R_SCENE_H

#include <math.h>
#include <string.h>

#include "sfm/sfm_r2r.h"
#include "sfm/sfm_rotation.h"
#include "sfm_test.h"

static inline void r2r_scene_identity(double *R)
{
    static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(R, I, sizeof I);
}

/* The noise-free measurements of step s under T (all three). */
static inline void r2r_scene_measure(const sfm_r2r_transform *T, sfm_r2r_step *s)
{
    double w[3], v[3];
    for (int r = 0; r < 3; r++)
        w[r] = T->C.m[3 * r] * s->t2.v[0] + T->C.m[3 * r + 1] * s->t2.v[1] +
               T->C.m[3 * r + 2] * s->t2.v[2] + T->p.v[r] - s->t1.v[r];
    double d = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    s->d = d;
    for (int r = 0; r < 3; r++)
        s->b1.v[r] = (s->R1.m[r] * w[0] + s->R1.m[3 + r] * w[1] + s->R1.m[6 + r] * w[2]) / d;
    for (int r = 0; r < 3; r++) /* C^T w */
        v[r] = T->C.m[r] * w[0] + T->C.m[3 + r] * w[1] + T->C.m[6 + r] * w[2];
    for (int r = 0; r < 3; r++)
        s->b2.v[r] = -(s->R2.m[r] * v[0] + s->R2.m[3 + r] * v[1] + s->R2.m[6 + r] * v[2]) / d;
}

/* A random truth: C uniform, p at 2..5 m. */
static inline void r2r_scene_truth(sfm_test_ctx *t, sfm_r2r_transform *T)
{
    sfm_test_random_rotation(t, T->C.m);
    double u[3], r = sfm_test_uniform(t, 2.0, 5.0);
    sfm_test_random_unit(t, u);
    for (int k = 0; k < 3; k++)
        T->p.v[k] = r * u[k];
}

/* n steps: step 0 the identity ego-motion, the others random orientations
 * and positions within +-span m; every measurement noise-free, has = 7. */
static inline void r2r_scene_steps(sfm_test_ctx *t, const sfm_r2r_transform *T, int n,
                                   double span, sfm_r2r_step *s)
{
    for (int k = 0; k < n; k++) {
        memset(&s[k], 0, sizeof s[k]);
        if (k == 0) {
            r2r_scene_identity(s[k].R1.m);
            r2r_scene_identity(s[k].R2.m);
        } else {
            sfm_test_random_rotation(t, s[k].R1.m);
            sfm_test_random_rotation(t, s[k].R2.m);
            for (int i = 0; i < 3; i++) {
                s[k].t1.v[i] = sfm_test_uniform(t, -span, span);
                s[k].t2.v[i] = sfm_test_uniform(t, -span, span);
            }
        }
        s[k].has = SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2;
        r2r_scene_measure(T, &s[k]);
    }
}

/* Unit v moved by independent N(0, sigma^2) angles along two tangent
 * directions, renormalised. */
static inline void r2r_scene_perturb_bearing(sfm_test_ctx *t, double sigma, double *v)
{
    double a[3] = {0, 0, 0}, e1[3], e2[3];
    int m = fabs(v[0]) <= fabs(v[1]) ? (fabs(v[0]) <= fabs(v[2]) ? 0 : 2)
                                     : (fabs(v[1]) <= fabs(v[2]) ? 1 : 2);
    a[m] = 1.0;
    e1[0] = v[1] * a[2] - v[2] * a[1];
    e1[1] = v[2] * a[0] - v[0] * a[2];
    e1[2] = v[0] * a[1] - v[1] * a[0];
    double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int i = 0; i < 3; i++)
        e1[i] /= l;
    e2[0] = v[1] * e1[2] - v[2] * e1[1];
    e2[1] = v[2] * e1[0] - v[0] * e1[2];
    e2[2] = v[0] * e1[1] - v[1] * e1[0];
    double n1 = sfm_test_normal(t, sigma), n2 = sfm_test_normal(t, sigma);
    double q[3];
    for (int i = 0; i < 3; i++)
        q[i] = v[i] + n1 * e1[i] + n2 * e2[i];
    l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    for (int i = 0; i < 3; i++)
        v[i] = q[i] / l;
}

/* Gaussian noise on every measurement the steps carry. */
static inline void r2r_scene_noise(sfm_test_ctx *t, double sd, double sb, sfm_r2r_step *s, int n)
{
    for (int k = 0; k < n; k++) {
        if (s[k].has & SFM_R2R_D)
            s[k].d += sfm_test_normal(t, sd);
        if (s[k].has & SFM_R2R_B1)
            r2r_scene_perturb_bearing(t, sb, s[k].b1.v);
        if (s[k].has & SFM_R2R_B2)
            r2r_scene_perturb_bearing(t, sb, s[k].b2.v);
    }
}

/* T moved by a rotation of angle rot about a random axis (left) and a
 * translation of length dp in a random direction. */
static inline void r2r_scene_perturb(sfm_test_ctx *t, const sfm_r2r_transform *T, double rot,
                                     double dp, sfm_r2r_transform *out)
{
    double u[3], aa[3], E[9];
    sfm_test_random_unit(t, u);
    for (int i = 0; i < 3; i++)
        aa[i] = rot * u[i];
    sfm_rot_from_axis_angle(aa, E);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out->C.m[3 * r + c] = E[3 * r] * T->C.m[c] + E[3 * r + 1] * T->C.m[3 + c] +
                                  E[3 * r + 2] * T->C.m[6 + c];
    sfm_test_random_unit(t, u);
    for (int i = 0; i < 3; i++)
        out->p.v[i] = T->p.v[i] + dp * u[i];
}

/* Error of est against truth as the refiner's tangent vector
 * e = (log(C_true C_est^T), p_true - p_est); returns the rotation angle and
 * writes |p error| to *perr. */
static inline double r2r_scene_error(const sfm_r2r_transform *est, const sfm_r2r_transform *truth,
                                     double e[6], double *perr)
{
    double M[9], aa[3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            M[3 * r + c] = truth->C.m[3 * r] * est->C.m[3 * c] +
                           truth->C.m[3 * r + 1] * est->C.m[3 * c + 1] +
                           truth->C.m[3 * r + 2] * est->C.m[3 * c + 2];
    sfm_rot_to_axis_angle(M, aa);
    double pe = 0.0;
    for (int i = 0; i < 3; i++) {
        if (e != NULL) {
            e[i] = aa[i];
            e[3 + i] = truth->p.v[i] - est->p.v[i];
        }
        pe += (truth->p.v[i] - est->p.v[i]) * (truth->p.v[i] - est->p.v[i]);
    }
    if (perr != NULL)
        *perr = sqrt(pe);
    return sqrt(aa[0] * aa[0] + aa[1] * aa[1] + aa[2] * aa[2]);
}

/* The canonical pattern of each base system, from its name in sfm_r2r.h
 * (index = sfm_r2r_system): step count, then each step's has-mask. */
#define R2R_D_ SFM_R2R_D
#define R2R_B1_ SFM_R2R_B1
#define R2R_B2_ SFM_R2R_B2
static const struct {
    const char *name;
    int n;
    unsigned has[6];
} r2r_scene_systems[SFM_R2R_SYS_COUNT_] = {
    {"", 0, {0}},
    {"DB1B2_D", 2, {R2R_D_ | R2R_B1_ | R2R_B2_, R2R_D_}},
    {"B1B2_B1", 2, {R2R_B1_ | R2R_B2_, R2R_B1_}},
    {"B1B2_D_D", 3, {R2R_B1_ | R2R_B2_, R2R_D_, R2R_D_}},
    {"DB1_DB1", 2, {R2R_D_ | R2R_B1_, R2R_D_ | R2R_B1_}},
    {"DB1_DB2", 2, {R2R_D_ | R2R_B1_, R2R_D_ | R2R_B2_}},
    {"DB1_B1_D", 3, {R2R_D_ | R2R_B1_, R2R_B1_, R2R_D_}},
    {"DB1_B2_D", 3, {R2R_D_ | R2R_B1_, R2R_B2_, R2R_D_}},
    {"DB1_D_D_D", 4, {R2R_D_ | R2R_B1_, R2R_D_, R2R_D_, R2R_D_}},
    {"B1_B1_B1", 3, {R2R_B1_, R2R_B1_, R2R_B1_}},
    {"B1_B1_B2", 3, {R2R_B1_, R2R_B1_, R2R_B2_}},
    {"B1_B1_D_D", 4, {R2R_B1_, R2R_B1_, R2R_D_, R2R_D_}},
    {"B1_B2_D_D", 4, {R2R_B1_, R2R_B2_, R2R_D_, R2R_D_}},
    {"B1_D_D_D_D", 5, {R2R_B1_, R2R_D_, R2R_D_, R2R_D_, R2R_D_}},
    {"D6", 6, {R2R_D_, R2R_D_, R2R_D_, R2R_D_, R2R_D_, R2R_D_}},
};

#endif
