/*
 * Benchmark of the epipolar and homography solvers on one generator of
 * noise-free random problems (rotation up to 0.5 rad about a random axis,
 * unit baseline in a random direction, points 2 to 10 units in front of both
 * cameras, focal 800 px; planes for the homographies).
 *
 *   solvers_bench                 table: us per call (median of 9 runs over
 *                                 the problem pool), solutions per call,
 *                                 ground-truth-found rate (within 1e-6)
 *   solvers_bench NAME CALLS      only CALLS calls of solver NAME (for
 *                                 callgrind: run twice with different CALLS
 *                                 and divide the difference in instructions)
 * NAME: 5pt 7pt 8pt f8pt h4pt hdlt.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sfm/sfm_rng.h"
#include "sfm/sfm_solvers.h"

#define POOL 1000
#define NPTS 8 /* points per problem (8pt and F 8pt use all of them) */
#define NDLT 20

typedef struct problem {
    double x1[3 * NPTS], x2[3 * NPTS]; /* bearings */
    double p1[2 * NPTS], p2[2 * NPTS]; /* pixels */
    double q1[2 * NDLT], q2[2 * NDLT]; /* plane points (pixels) */
    double E[9], F[9], H[9];           /* truth, unit Frobenius */
} problem;

static problem pool[POOL];
static sfm_rng rng;

static double unif(double a, double b) { return a + (b - a) * sfm_rng_uniform(&rng); }

static void mm(const double *A, const double *B, double *C)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

static void unit9(double *M, int fix_det_sign)
{
    double s = 0.0;
    for (int i = 0; i < 9; i++)
        s += M[i] * M[i];
    s = 1.0 / sqrt(s);
    if (fix_det_sign) {
        double d = M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
                   M[2] * (M[3] * M[7] - M[4] * M[6]);
        if (d < 0.0)
            s = -s;
    }
    for (int i = 0; i < 9; i++)
        M[i] *= s;
}

/* Rotation by a uniform angle in [0, 0.5] rad about a random axis (camera 2
 * still sees the points in front of camera 1). */
static void random_rotation(double R[9])
{
    double a[3], n = 0.0;
    for (int i = 0; i < 3; i++) {
        a[i] = sfm_rng_normal(&rng);
        n += a[i] * a[i];
    }
    n = sqrt(n);
    double h = 0.5 * unif(0.0, 0.5), sh = sin(h) / n;
    double w = cos(h), x = a[0] * sh, y = a[1] * sh, z = a[2] * sh;
    R[0] = 1 - 2 * (y * y + z * z); R[1] = 2 * (x * y - w * z);     R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z);     R[4] = 1 - 2 * (x * x + z * z); R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y);     R[7] = 2 * (y * z + w * x);     R[8] = 1 - 2 * (x * x + y * y);
}

static void make_problem(problem *P)
{
    double R[9], C[3], t[3];
    random_rotation(R);
    double n = 0.0;
    for (int i = 0; i < 3; i++) {
        C[i] = sfm_rng_normal(&rng);
        n += C[i] * C[i];
    }
    for (int i = 0; i < 3; i++)
        C[i] /= sqrt(n);
    for (int i = 0; i < 3; i++)
        t[i] = -(R[3 * i] * C[0] + R[3 * i + 1] * C[1] + R[3 * i + 2] * C[2]);
    const double f = 800.0, cx = 320.0, cy = 240.0;
    for (int k = 0; k < NPTS; k++) {
        double X[3], Y[3], d;
        do {
            d = unif(2.0, 10.0);
            X[0] = d * unif(-0.6, 0.6);
            X[1] = d * unif(-0.45, 0.45);
            X[2] = d;
            for (int i = 0; i < 3; i++)
                Y[i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2] + t[i];
        } while (Y[2] < 0.1);
        double nx = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
        double ny = sqrt(Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]);
        for (int i = 0; i < 3; i++) {
            P->x1[3 * k + i] = X[i] / nx;
            P->x2[3 * k + i] = Y[i] / ny;
        }
        P->p1[2 * k] = f * X[0] / X[2] + cx;
        P->p1[2 * k + 1] = f * X[1] / X[2] + cy;
        P->p2[2 * k] = f * Y[0] / Y[2] + cx;
        P->p2[2 * k + 1] = f * Y[1] / Y[2] + cy;
    }
    double T[9] = {0, -t[2], t[1], t[2], 0, -t[0], -t[1], t[0], 0};
    mm(T, R, P->E);
    unit9(P->E, 0);
    double Ki[9] = {1 / f, 0, -cx / f, 0, 1 / f, -cy / f, 0, 0, 1};
    double KiT[9] = {Ki[0], Ki[3], Ki[6], Ki[1], Ki[4], Ki[7], Ki[2], Ki[5], Ki[8]};
    double M[9];
    mm(KiT, P->E, M);
    mm(M, Ki, P->F);
    unit9(P->F, 0);
    /* plane z = 5 (tilted by the random rotation below), small rotation */
    double R2[9], nrm[3] = {unif(-0.3, 0.3), unif(-0.3, 0.3), 1.0}, dpl = unif(3.0, 8.0);
    double nn = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + 1.0);
    for (int i = 0; i < 3; i++)
        nrm[i] /= nn;
    double ax[3] = {unif(-0.2, 0.2), unif(-0.2, 0.2), unif(-0.2, 0.2)};
    /* first-order rotation, re-orthonormalized through a quaternion */
    double qn = sqrt(1.0 + ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    double w = 1.0 / qn, x = ax[0] / qn, y = ax[1] / qn, z = ax[2] / qn;
    R2[0] = 1 - 2 * (y * y + z * z); R2[1] = 2 * (x * y - w * z);     R2[2] = 2 * (x * z + w * y);
    R2[3] = 2 * (x * y + w * z);     R2[4] = 1 - 2 * (x * x + z * z); R2[5] = 2 * (y * z - w * x);
    R2[6] = 2 * (x * z - w * y);     R2[7] = 2 * (y * z + w * x);     R2[8] = 1 - 2 * (x * x + y * y);
    double t2[3] = {unif(-0.5, 0.5), unif(-0.5, 0.5), unif(-0.5, 0.5)};
    double A[9], K[9] = {f, 0, cx, 0, f, cy, 0, 0, 1};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            A[3 * r + c] = R2[3 * r + c] + t2[r] * nrm[c] / dpl;
    mm(K, A, M);
    mm(M, Ki, P->H);
    unit9(P->H, 1);
    for (int k = 0; k < NDLT; k++) {
        double u = unif(-0.5, 0.5), v = unif(-0.4, 0.4);
        double zz = dpl / (nrm[0] * u + nrm[1] * v + nrm[2]);
        double X[3] = {u * zz, v * zz, zz}, Y[3];
        for (int i = 0; i < 3; i++)
            Y[i] = R2[3 * i] * X[0] + R2[3 * i + 1] * X[1] + R2[3 * i + 2] * X[2] + t2[i];
        P->q1[2 * k] = f * X[0] / X[2] + cx;
        P->q1[2 * k + 1] = f * X[1] / X[2] + cy;
        P->q2[2 * k] = f * Y[0] / Y[2] + cx;
        P->q2[2 * k + 1] = f * Y[1] / Y[2] + cy;
    }
}

static double dist_proj(const double *A, const double *B)
{
    double dp = 0.0, dm = 0.0, na = 0.0;
    for (int i = 0; i < 9; i++)
        na += A[i] * A[i];
    na = 1.0 / sqrt(na);
    for (int i = 0; i < 9; i++) {
        dp += (A[i] * na - B[i]) * (A[i] * na - B[i]);
        dm += (A[i] * na + B[i]) * (A[i] * na + B[i]);
    }
    return sqrt(dp < dm ? dp : dm);
}

enum { S_5PT, S_7PT, S_8PT, S_F8PT, S_H4PT, S_HDLT, S_COUNT };
static const char *const NAMES[S_COUNT] = {"5pt", "7pt", "8pt", "f8pt", "h4pt", "hdlt"};
static const char *const LABELS[S_COUNT] = {
    "sfm_relpose_5pt", "sfm_fundamental_7pt", "sfm_relpose_8pt (n=8)", "sfm_fundamental_8pt (n=8)",
    "sfm_homography_4pt", "sfm_homography_dlt (n=20)"};

/* One call of solver s on problem P; returns the count and whether the truth
 * is among the solutions. */
static int call(int s, const problem *P, sfm_mat3 *out)
{
    switch (s) {
    case S_5PT: return sfm_relpose_5pt(P->x1, P->x2, out);
    case S_7PT: return sfm_fundamental_7pt(P->p1, P->p2, out);
    case S_8PT: return sfm_relpose_8pt(P->x1, P->x2, NPTS, out);
    case S_F8PT: return sfm_fundamental_8pt(P->p1, P->p2, NPTS, out);
    case S_H4PT: return sfm_homography_4pt(P->q1, P->q2, out);
    default: return sfm_homography_dlt(P->q1, P->q2, NDLT, out);
    }
}

static const double *truth(int s, const problem *P)
{
    if (s == S_5PT || s == S_8PT)
        return P->E;
    if (s == S_7PT || s == S_F8PT)
        return P->F;
    return P->H;
}

static double now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e6 + ts.tv_nsec * 1e-3;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    sfm_rng_seed(&rng, 20261122);
    for (int i = 0; i < POOL; i++)
        make_problem(&pool[i]);
    sfm_mat3 out[SFM_RELPOSE_5PT_MAX_SOLUTIONS];
    volatile long sink = 0;

    if (argc == 3) {
        int s = -1;
        for (int k = 0; k < S_COUNT; k++)
            if (strcmp(argv[1], NAMES[k]) == 0)
                s = k;
        long calls = atol(argv[2]);
        if (s < 0 || calls < 0) {
            fprintf(stderr, "usage: %s [5pt|7pt|8pt|f8pt|h4pt|hdlt CALLS]\n", argv[0]);
            return 2;
        }
        for (long i = 0; i < calls; i++)
            sink += call(s, &pool[i % POOL], out);
        return 0;
    }

    printf("%-28s %10s %10s %12s\n", "solver (noise-free, general)", "us/call", "sols/call",
           "truth found");
    for (int s = 0; s < S_COUNT; s++) {
        long nsol = 0, found = 0;
        for (int i = 0; i < POOL; i++) {
            int n = call(s, &pool[i], out);
            double best = INFINITY;
            for (int k = 0; k < n; k++) {
                double d = dist_proj(out[k].m, truth(s, &pool[i]));
                if (d < best)
                    best = d;
            }
            nsol += n > 0 ? n : 0;
            found += best < 1e-6;
        }
        enum { RUNS = 9 };
        double t[RUNS];
        int reps = s == S_H4PT ? 200 : (s == S_5PT ? 5 : 20);
        for (int r = 0; r < RUNS; r++) {
            double t0 = now_us();
            for (int rep = 0; rep < reps; rep++)
                for (int i = 0; i < POOL; i++)
                    sink += call(s, &pool[i], out);
            t[r] = (now_us() - t0) / ((double)reps * POOL);
        }
        qsort(t, RUNS, sizeof t[0], cmp);
        printf("%-28s %10.3f %10.2f %11.2f%%\n", LABELS[s], t[RUNS / 2], (double)nsol / POOL,
               100.0 * found / POOL);
    }
    (void)sink;
    return 0;
}
