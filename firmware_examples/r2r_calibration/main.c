/*
 * Two robots find their relative transform from the ranges and bearings
 * they exchange: robot 1 (a ground vehicle driving an arc) and robot 2 (a
 * drone circling and climbing) each know their own ego-motion from
 * odometry; at every step they exchange a range (radio time of flight) and
 * the bearings each camera sees of the other. A few measurements are gross
 * outliers (a multipath range, a false detection). sfm_r2r_ransac draws
 * minimal sets of six equations, solves them (sfm_r2r_solve), scores every
 * measurement by its normalised residual and refits on the inliers
 * (sfm_r2r_refine, which also gives the 6 x 6 covariance).
 *
 * The same file builds for Linux (a host program) and for a bare-metal
 * Cortex-M7 (no heap, no OS, static workspace; under qemu-system-arm with
 * semihosting). The simulation is deterministic (the library's sfm_rng).
 * It prints the estimate, its 1-sigma bounds, the errors against the
 * simulated truth and which measurements were rejected; exit status 0 when
 * the rotation error is below 1 deg, the position error below 0.1 m and
 * every injected outlier is rejected.
 *
 * Frames (sfm_r2r.h): {1}, {2} the robots at the first step; the answer is
 * (C, p) with x_{1} = C x_{2} + p.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm.h"

enum { NSTEP = 12 };

#define PI 3.14159265358979323846
#define SIGMA_D 0.05 /* m */
#define SIGMA_B 0.01 /* rad */

static sfm_r2r_step steps[NSTEP];
static unsigned inliers[NSTEP];
static unsigned outlier[NSTEP];
static unsigned char workspace[64 * 1024]; /* 38.9 KB with all fourteen base systems */

#if defined(__arm__)
#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#endif

/* Fixed-point print (newlib-nano's printf has no %f). */
static void pfix(const char *label, const double *v, int n)
{
    printf("%s", label);
    for (int k = 0; k < n; k++) {
        long m = lround(v[k] * 1e6);
        printf(" %s%ld.%06ld", m < 0 ? "-" : "", labs(m) / 1000000, labs(m) % 1000000);
    }
    printf("\n");
}

static void rot_zyx(double yaw, double pitch, double roll, double *R)
{
    double aa[3] = {0, 0, yaw}, Rz[9], Ry[9], Rx[9], T[9];
    sfm_rot_from_axis_angle(aa, Rz);
    aa[2] = 0;
    aa[1] = pitch;
    sfm_rot_from_axis_angle(aa, Ry);
    aa[1] = 0;
    aa[0] = roll;
    sfm_rot_from_axis_angle(aa, Rx);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            T[3 * r + c] = 0;
            for (int k = 0; k < 3; k++)
                T[3 * r + c] += Rz[3 * r + k] * Ry[3 * k + c];
        }
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            R[3 * r + c] = 0;
            for (int k = 0; k < 3; k++)
                R[3 * r + c] += T[3 * r + k] * Rx[3 * k + c];
        }
}

/* y = A^T x, y = A x */
static void mtv(const double *A, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = A[r] * x[0] + A[3 + r] * x[1] + A[6 + r] * x[2];
}

static void mtm(const double *A, const double *B, double *C) /* C = A^T B */
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c];
}

/* A unit vector moved by N(0, s^2) angles about two axes normal to it. */
static void jitter(sfm_rng *rng, double s, double *b)
{
    double a[3] = {sfm_rng_normal(rng) * s, sfm_rng_normal(rng) * s, sfm_rng_normal(rng) * s};
    double k = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; /* drop the part along b */
    for (int i = 0; i < 3; i++)
        a[i] -= k * b[i];
    double R[9], v[3];
    sfm_rot_from_axis_angle(a, R);
    for (int r = 0; r < 3; r++)
        v[r] = R[3 * r] * b[0] + R[3 * r + 1] * b[1] + R[3 * r + 2] * b[2];
    memcpy(b, v, sizeof v);
}

/* The simulated world: robot poses (body to world), ego-motions relative
 * to the first step, measurements with noise, three outliers. */
static void simulate(sfm_r2r_transform *truth)
{
    sfm_rng rng;
    sfm_rng_seed(&rng, 2024u);
    double W1[NSTEP][9], P1[NSTEP][3], W2[NSTEP][9], P2[NSTEP][3];
    for (int k = 0; k < NSTEP; k++) {
        double a = 0.25 * k; /* robot 1: an arc of radius 4 m on the ground */
        P1[k][0] = 4.0 * sin(a);
        P1[k][1] = 4.0 * (1.0 - cos(a));
        P1[k][2] = 0.0;
        rot_zyx(a, 0.02 * sin(3.0 * a), 0.01 * cos(2.0 * a), W1[k]);
        double b = -0.4 * k; /* robot 2: a climbing circle of radius 2 m */
        P2[k][0] = 7.0 + 2.0 * cos(b);
        P2[k][1] = 3.0 + 2.0 * sin(b);
        P2[k][2] = 1.5 + 0.15 * k;
        rot_zyx(b - PI / 2, 0.1 * sin(b), 0.05, W2[k]);
    }
    double v[3];
    mtm(W1[0], W2[0], truth->C.m);
    for (int i = 0; i < 3; i++)
        v[i] = P2[0][i] - P1[0][i];
    mtv(W1[0], v, truth->p.v);
    for (int k = 0; k < NSTEP; k++) {
        sfm_r2r_step *s = &steps[k];
        memset(s, 0, sizeof *s);
        mtm(W1[0], W1[k], s->R1.m);
        mtm(W2[0], W2[k], s->R2.m);
        for (int i = 0; i < 3; i++)
            v[i] = P1[k][i] - P1[0][i];
        mtv(W1[0], v, s->t1.v);
        for (int i = 0; i < 3; i++)
            v[i] = P2[k][i] - P2[0][i];
        mtv(W2[0], v, s->t2.v);
        for (int i = 0; i < 3; i++)
            v[i] = P2[k][i] - P1[k][i];
        double d = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        s->has = SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2;
        s->d = d + SIGMA_D * sfm_rng_normal(&rng);
        mtv(W1[k], v, s->b1.v);
        mtv(W2[k], v, s->b2.v);
        for (int i = 0; i < 3; i++) {
            s->b1.v[i] /= d;
            s->b2.v[i] /= -d;
        }
        jitter(&rng, SIGMA_B, s->b1.v);
        jitter(&rng, SIGMA_B, s->b2.v);
        if (k == 3 || k == 8) { /* every fourth step robot 2's camera misses */
            s->has &= ~SFM_R2R_B2;
        }
    }
    /* outliers: a multipath range, a false detection by each camera */
    steps[5].d += 1.7;
    outlier[5] |= SFM_R2R_D;
    steps[9].b1.v[0] = -steps[9].b1.v[0];
    steps[9].b1.v[2] += 0.4;
    outlier[9] |= SFM_R2R_B1;
    steps[2].b2.v[1] += 0.5;
    outlier[2] |= SFM_R2R_B2;
}

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    sfm_r2r_transform truth, est;
    simulate(&truth);
    size_t need = sfm_r2r_ransac_workspace_size(NSTEP);
    printf("libsfm %d r2r calibration: %d steps, workspace %u of %u bytes\n", sfm_version(), NSTEP,
           (unsigned)need, (unsigned)sizeof workspace);
    if (need == 0 || need > sizeof workspace) {
        printf("workspace too small: %s\n", sfm_status_str(SFM_E_WORKSPACE));
        return 1;
    }
    sfm_r2r_ransac_options opt;
    sfm_r2r_ransac_default_options(&opt);
    opt.refine.sigma_d = SIGMA_D;
    opt.refine.sigma_b = SIGMA_B;
    double cov[36];
    sfm_ransac_stats st;
#if defined(__arm__)
    SYST_RVR = 0x00FFFFFFu;
    SYST_CVR = 0;
    SYST_CSR = 5u; /* enabled, processor clock, no interrupt */
    uint32_t t0 = SYST_CVR;
#endif
    int n = sfm_r2r_ransac(steps, NSTEP, &opt, &est, inliers, cov, &st, workspace, need);
#if defined(__arm__)
    uint32_t ticks = (t0 - SYST_CVR) & 0x00FFFFFFu;
#endif
    if (n < 0) {
        printf("calibration failed: %s\n", sfm_status_str(n));
        return 1;
    }
    int n_meas = 0;
    for (int k = 0; k < NSTEP; k++)
        n_meas += (steps[k].has & 1u) + ((steps[k].has >> 1) & 1u) + ((steps[k].has >> 2) & 1u);
    printf("%d of %d measurements inliers, %d samples, %d hypotheses\n", n, n_meas, st.iterations,
           st.models);
#if defined(__arm__)
    /* under qemu -icount shift=0 a 25 MHz SysTick tick is 40 instructions;
     * the count wraps above 16.7 M ticks */
    printf("SysTick ticks %lu (%lu instructions under -icount shift=0)\n", (unsigned long)ticks,
           40ul * ticks);
#endif
    pfix("C", est.C.m, 9);
    pfix("p", est.p.v, 3);
    double sig[6];
    for (int i = 0; i < 6; i++)
        sig[i] = sqrt(cov[7 * i]);
    pfix("1-sigma (rotation rad x3, position m x3)", sig, 6);
    double ang = 0.0, pe = 0.0;
    sfm_rot_angle_between(est.C.m, truth.C.m, &ang);
    for (int i = 0; i < 3; i++)
        pe += (est.p.v[i] - truth.p.v[i]) * (est.p.v[i] - truth.p.v[i]);
    pe = sqrt(pe);
    printf("rotation error %d millideg, position error %d mm\n", (int)lround(ang * 180e3 / PI),
           (int)lround(pe * 1e3));
    int missed = 0, dropped = 0;
    for (int k = 0; k < NSTEP; k++) {
        unsigned rej = steps[k].has & ~inliers[k];
        if (rej)
            printf("step %d rejected:%s%s%s%s\n", k, (rej & SFM_R2R_D) ? " d" : "",
                   (rej & SFM_R2R_B1) ? " b1" : "", (rej & SFM_R2R_B2) ? " b2" : "",
                   (rej & ~outlier[k]) ? " (a true measurement)" : "");
        missed += (outlier[k] & inliers[k]) != 0;
        dropped += (rej & ~outlier[k]) != 0;
    }
    int ok = ang < PI / 180.0 && pe < 0.1 && missed == 0;
    printf("%s: %d outliers accepted, %d true measurements rejected\n", ok ? "PASS" : "FAIL", missed,
           dropped);
    return ok ? 0 : 1;
}
