/*
 * Benchmark of the pose solvers and triangulation on one synthetic
 * generator: median microseconds per call over repeated runs, solutions per
 * call and the ground-truth-found rate (some solution within 1e-6 of truth).
 *
 *   pose_bench                      the table
 *   pose_bench --calls N SOLVER     N calls only, no timing, no output: for
 *                                   instruction counts, run it under
 *                                   callgrind with two values of N and divide
 *                                   the difference (bench/pose_callgrind.sh)
 * SOLVER: p3p, upright3pt, essential, tri_dlt, tri_midpoint, tri_optimal.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sfm/sfm.h"

#define POOL 256
#define PI 3.14159265358979323846

static sfm_rng rng;

static double uni(double lo, double hi)
{
    return lo + (hi - lo) * sfm_rng_uniform(&rng);
}

static void unit3(double v[3])
{
    double n;
    do {
        for (int k = 0; k < 3; k++)
            v[k] = sfm_rng_normal(&rng);
        n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (n < 1e-6);
    for (int k = 0; k < 3; k++)
        v[k] /= n;
}

static void rand_rot(double R[9])
{
    double q[4], n;
    do {
        for (int i = 0; i < 4; i++)
            q[i] = sfm_rng_normal(&rng);
        n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    } while (n < 1e-6);
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    R[0] = 1 - 2 * (y * y + z * z);
    R[1] = 2 * (x * y - w * z);
    R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z);
    R[4] = 1 - 2 * (x * x + z * z);
    R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y);
    R[7] = 2 * (y * z + w * x);
    R[8] = 1 - 2 * (x * x + y * y);
}

static void mv(const double R[9], const double x[3], double y[3])
{
    for (int r = 0; r < 3; r++)
        y[r] = R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2];
}

static void nrm(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        v[k] /= n;
}

typedef struct problem {
    double R[9], t[3];
    double x[9], X[9];      /* P3P: bearings, world points */
    double x1[9], x2[9], d1[3], d2[3]; /* upright */
    sfm_mat3 E;
    double ex1[3 * 50], ex2[3 * 50];
    double P[24], xp[4], f[6];
} problem;

static problem pool[POOL];

static void make_pool(void)
{
    for (int p = 0; p < POOL; p++) {
        problem *q = &pool[p];
        rand_rot(q->R);
        unit3(q->t);
        /* P3P: points in front of camera (R, t), world X */
        double tw[3] = {q->t[0] * 2, q->t[1] * 2, q->t[2] * 2};
        for (int i = 0; i < 3; i++) {
            double d = uni(1, 10), xc[3] = {uni(-0.8, 0.8) * d, uni(-0.8, 0.8) * d, d};
            double b[3] = {xc[0], xc[1], xc[2]};
            nrm(b);
            memcpy(q->x + 3 * i, b, sizeof b);
            double v[3] = {xc[0] - tw[0], xc[1] - tw[1], xc[2] - tw[2]};
            for (int r = 0; r < 3; r++)
                q->X[3 * i + r] = q->R[r] * v[0] + q->R[3 + r] * v[1] + q->R[6 + r] * v[2];
        }
        /* upright: frame-1 points, x2 = R x1 + t, d2 = R d1 */
        unit3(q->d1);
        mv(q->R, q->d1, q->d2);
        for (int i = 0; i < 3; i++) {
            double d = uni(2, 10), X[3] = {uni(-0.8, 0.8) * d, uni(-0.8, 0.8) * d, d}, Y[3];
            mv(q->R, X, Y);
            for (int k = 0; k < 3; k++)
                Y[k] += q->t[k];
            nrm(X);
            nrm(Y);
            memcpy(q->x1 + 3 * i, X, sizeof X);
            memcpy(q->x2 + 3 * i, Y, sizeof Y);
        }
        /* essential with 50 bearing pairs */
        double S[9] = {0, -q->t[2], q->t[1], q->t[2], 0, -q->t[0], -q->t[1], q->t[0], 0};
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                q->E.m[3 * r + c] = S[3 * r] * q->R[c] + S[3 * r + 1] * q->R[3 + c] + S[3 * r + 2] * q->R[6 + c];
        for (int i = 0; i < 50; i++) {
            double d = uni(2, 20), X[3] = {uni(-0.8, 0.8) * d, uni(-0.8, 0.8) * d, d}, Y[3];
            mv(q->R, X, Y);
            for (int k = 0; k < 3; k++)
                Y[k] += q->t[k];
            nrm(X);
            nrm(Y);
            memcpy(q->ex1 + 3 * i, X, sizeof X);
            memcpy(q->ex2 + 3 * i, Y, sizeof Y);
        }
        /* triangulation: [I|0] and [R|t], one point, 1e-3 noise */
        memset(q->P, 0, sizeof q->P);
        q->P[0] = q->P[5] = q->P[10] = 1.0;
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                q->P[12 + 4 * r + c] = q->R[3 * r + c];
            q->P[12 + 4 * r + 3] = q->t[r];
        }
        double d = uni(2, 10), X[3] = {uni(-0.5, 0.5) * d, uni(-0.5, 0.5) * d, d}, Y[3];
        mv(q->R, X, Y);
        for (int k = 0; k < 3; k++)
            Y[k] += q->t[k];
        q->xp[0] = X[0] / X[2] + uni(-1e-3, 1e-3);
        q->xp[1] = X[1] / X[2] + uni(-1e-3, 1e-3);
        q->xp[2] = Y[0] / Y[2] + uni(-1e-3, 1e-3);
        q->xp[3] = Y[1] / Y[2] + uni(-1e-3, 1e-3);
        q->f[0] = q->xp[0];
        q->f[1] = q->xp[1];
        q->f[2] = 1.0;
        q->f[3] = q->xp[2];
        q->f[4] = q->xp[3];
        q->f[5] = 1.0;
    }
}

static volatile double sink;
static sfm_pose out[8];

/* One call of solver `which` on problem q; returns the solution count. */
static int call(int which, const problem *q)
{
    int n = 0;
    switch (which) {
    case 0:
        n = sfm_p3p(q->x, q->X, out);
        break;
    case 1:
        n = sfm_relpose_upright_3pt(q->x1, q->x2, q->d1, q->d2, out);
        break;
    case 2: {
        int cnt[4];
        n = sfm_essential_to_poses(&q->E, q->ex1, q->ex2, 50, out, cnt);
        break;
    }
    case 3: {
        double X[3];
        int fl;
        n = sfm_triangulate_dlt(2, q->P, 1, q->xp, X, &fl);
        sink = X[0];
        break;
    }
    case 4: {
        double X[3];
        int fl;
        sfm_pose ps[2];
        memset(ps, 0, sizeof ps);
        ps[0].R[0] = ps[0].R[4] = ps[0].R[8] = 1.0;
        memcpy(ps[1].R, q->R, sizeof q->R);
        memcpy(ps[1].t, q->t, sizeof q->t);
        n = sfm_triangulate_midpoint(2, ps, 1, q->f, X, &fl);
        sink = X[0];
        break;
    }
    case 5: {
        double X[3];
        int fl;
        double x1[2] = {q->xp[0], q->xp[1]}, x2[2] = {q->xp[2], q->xp[3]};
        n = sfm_triangulate_optimal2(q->P, q->P + 12, 1, x1, x2, X, &fl);
        sink = X[0];
        break;
    }
    }
    return n;
}

static const char *names[] = {"p3p", "upright3pt", "essential", "tri_dlt", "tri_midpoint",
                              "tri_optimal"};
static const char *labels[] = {"sfm_p3p", "sfm_relpose_upright_3pt",
                               "sfm_essential_to_poses (50 pts)", "sfm_triangulate_dlt (2 views)",
                               "sfm_triangulate_midpoint (2 v)", "sfm_triangulate_optimal2"};
#define NSOLVERS 6

static int found_truth(int which, const problem *q, int n)
{
    if (which > 2)
        return 1;
    for (int s = 0; s < n; s++) {
        const double *t = which == 0 ? NULL : q->t;
        double e = 0.0;
        for (int i = 0; i < 9; i++)
            e = fmax(e, fabs(out[s].R[i] - q->R[i]));
        if (which == 0) {
            double tw[3];
            mv(q->R, (double[3]){q->t[0] * 2, q->t[1] * 2, q->t[2] * 2}, tw);
            /* x_cam = R X + t with X = R^T (xc - 2 t0): t = 2 t0 */
            for (int i = 0; i < 3; i++)
                e = fmax(e, fabs(out[s].t[i] - 2.0 * q->t[i]) / 3.0);
            (void)tw;
        } else {
            for (int i = 0; i < 3; i++)
                e = fmax(e, fabs(out[s].t[i] - t[i]));
        }
        if (e < 1e-6)
            return 1;
    }
    return 0;
}

static double now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return ts.tv_sec * 1e6 + ts.tv_nsec * 1e-3;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    sfm_rng_seed(&rng, 12345);
    make_pool();
    if (argc == 4 && strcmp(argv[1], "--calls") == 0) {
        long calls = atol(argv[2]);
        int which = -1;
        for (int k = 0; k < NSOLVERS; k++)
            if (strcmp(argv[3], names[k]) == 0)
                which = k;
        if (which < 0 || calls < 0) {
            fprintf(stderr, "unknown solver %s\n", argv[3]);
            return 2;
        }
        long total = 0;
        for (long c = 0; c < calls; c++)
            total += call(which, &pool[c % POOL]);
        sink = (double)total;
        return 0;
    }
    printf("pose solvers, %d problems per run, median of 25 runs (gcc -O2, no -march)\n", POOL);
    printf("%-34s %12s %10s %10s\n", "solver", "us/call", "sols/call", "truth");
    for (int which = 0; which < NSOLVERS; which++) {
        long nsol = 0, found = 0;
        for (int p = 0; p < POOL; p++) {
            int n = call(which, &pool[p]);
            nsol += n > 0 ? n : 0;
            found += found_truth(which, &pool[p], n);
        }
        enum { RUNS = 25, REP = 20 };
        double per[RUNS];
        for (int r = 0; r < RUNS; r++) {
            double t0 = now_us();
            for (int rep = 0; rep < REP; rep++)
                for (int p = 0; p < POOL; p++)
                    call(which, &pool[p]);
            per[r] = (now_us() - t0) / (REP * POOL);
        }
        qsort(per, RUNS, sizeof per[0], cmp_double);
        if (which <= 2)
            printf("%-34s %12.3f %10.2f %10.4f\n", labels[which], per[RUNS / 2],
                   (double)nsol / POOL, (double)found / POOL);
        else
            printf("%-34s %12.3f %10s %10s\n", labels[which], per[RUNS / 2], "-", "-");
    }
    return 0;
}
