/*
 * Benchmark of sfm_r2r_solve per base system, on noise-free random scenes
 * (both robots at random orientations and positions in a 6 m cube, at
 * least 0.5 m apart, measurements from world geometry), each system's
 * pattern in canonical order; plus sequences of 12 steps carrying every
 * measurement (the minimal-subset path).
 *
 *   r2r_bench                 table: us per call (median of 9 passes over
 *                             the pool), of which the base solver alone,
 *                             real solutions per call, truth-found rate
 *                             (within 1e-6), status when not solvable
 *   r2r_bench NAME CALLS      only CALLS calls of system NAME (for
 *                             callgrind: run twice with different CALLS
 *                             and divide the difference in instructions)
 * NAME: db1b2_d ... d6 (the descriptor names), or over12.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sfm/sfm_r2r.h"
#include "sfm/sfm_rng.h"
#include "solvers/r2r_solve_internal.h"

#define POOL 200
#define NOVER 12

typedef struct problem {
    int n;
    sfm_r2r_step s[NOVER];
    sfm_r2r_transform T;
} problem;

static problem pool[POOL];
static sfm_rng rng;
static double ws[1 << 15];
static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];

static const char *const names[SFM_R2R_SYS_COUNT_ + 1] = {
    "", "db1b2_d", "b1b2_b1", "b1b2_d_d", "db1_db1", "db1_db2", "db1_b1_d", "db1_b2_d",
    "db1_d_d_d", "b1_b1_b1", "b1_b1_b2", "b1_b1_d_d", "b1_b2_d_d", "b1_d_d_d_d", "d6", "over12"};

static double unif(double a, double b) { return a + (b - a) * sfm_rng_uniform(&rng); }

static void rand_rot(double *R)
{
    double q[4], s = 0.0;
    for (int i = 0; i < 4; i++) {
        q[i] = unif(-1.0, 1.0);
        s += q[i] * q[i];
    }
    s = 1.0 / sqrt(s);
    double w = q[0] * s, x = q[1] * s, y = q[2] * s, z = q[3] * s;
    double M[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
    memcpy(R, M, sizeof M);
}

static void tmul(const double *A, const double *B, double *C)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c];
}

static void tmv(const double *A, const double *x, double *y)
{
    for (int c = 0; c < 3; c++)
        y[c] = A[c] * x[0] + A[3 + c] * x[1] + A[6 + c] * x[2];
}

static void make(problem *pb, int n, const unsigned *has)
{
    double W1[NOVER][9], W2[NOVER][9], P1[NOVER][3], P2[NOVER][3];
    for (int k = 0; k < n; k++) {
        rand_rot(W1[k]);
        rand_rot(W2[k]);
        double v[3], dd;
        do {
            for (int i = 0; i < 3; i++) {
                P1[k][i] = unif(-3.0, 3.0);
                P2[k][i] = unif(-3.0, 3.0);
                v[i] = P2[k][i] - P1[k][i];
            }
            dd = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        } while (dd < 0.5);
    }
    pb->n = n;
    tmul(W1[0], W2[0], pb->T.C.m);
    double d0[3] = {P2[0][0] - P1[0][0], P2[0][1] - P1[0][1], P2[0][2] - P1[0][2]};
    tmv(W1[0], d0, pb->T.p.v);
    for (int k = 0; k < n; k++) {
        sfm_r2r_step *s = pb->s + k;
        double a[3], b[3], v[3];
        memset(s, 0, sizeof *s);
        tmul(W1[0], W1[k], s->R1.m);
        tmul(W2[0], W2[k], s->R2.m);
        for (int i = 0; i < 3; i++) {
            a[i] = P1[k][i] - P1[0][i];
            b[i] = P2[k][i] - P2[0][i];
            v[i] = P2[k][i] - P1[k][i];
        }
        tmv(W1[0], a, s->t1.v);
        tmv(W2[0], b, s->t2.v);
        double d = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        s->has = has[k];
        s->d = d;
        tmv(W1[k], v, s->b1.v);
        tmv(W2[k], v, s->b2.v);
        for (int i = 0; i < 3; i++) {
            s->b1.v[i] /= d;
            s->b2.v[i] /= -d;
        }
    }
}

static void fill(int sys)
{
    unsigned has[NOVER];
    int n;
    if (sys == SFM_R2R_SYS_COUNT_) {
        n = NOVER;
        for (int k = 0; k < n; k++)
            has[k] = 7u;
    } else {
        n = sfmi_r2r_patterns[sys][0];
        for (int k = 0; k < n; k++)
            has[k] = sfmi_r2r_patterns[sys][1 + k];
    }
    for (int i = 0; i < POOL; i++)
        make(pool + i, n, has);
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
    return x < y ? -1 : x > y;
}

static int solve(const problem *pb)
{
    return sfm_r2r_solve(pb->s, pb->n, out, ws, sizeof ws);
}

int main(int argc, char **argv)
{
    sfm_rng_seed(&rng, 20261202u);
    if (argc == 3) {
        int sys = 0;
        for (int s = 1; s <= SFM_R2R_SYS_COUNT_; s++)
            if (!strcmp(argv[1], names[s]))
                sys = s;
        if (!sys) {
            fprintf(stderr, "unknown system %s\n", argv[1]);
            return 2;
        }
        long calls = atol(argv[2]);
        fill(sys);
        volatile int sink = 0;
        for (long i = 0; i < calls; i++)
            sink += solve(pool + i % POOL);
        (void)sink;
        return 0;
    }
    printf("sfm_r2r_solve per base system (%d random noise-free scenes each, median of 9 passes)\n", POOL);
    printf("%-11s %9s %9s %9s %8s  %s\n", "system", "us/call", "solver", "sols", "truth", "status");
    for (int sys = 1; sys <= SFM_R2R_SYS_COUNT_; sys++) {
        fill(sys);
        int first = solve(pool);
        if (first < 0 && first != SFM_E_DEGENERATE) {
            printf("%-11s %9s %9s %9s %8s  %s\n", names[sys], "-", "-", "-", "-", sfm_status_str(first));
            continue;
        }
        double t[9], ts[9];
        long sols = 0, truth = 0, fails = 0;
        for (int i = 0; i < POOL; i++) {
            int n = solve(pool + i);
            if (n < 0) {
                fails++;
                continue;
            }
            sols += n;
            for (int j = 0; j < n; j++) {
                double e = 0.0;
                for (int q = 0; q < 9; q++)
                    e = fmax(e, fabs(out[j].C.m[q] - pool[i].T.C.m[q]));
                for (int q = 0; q < 3; q++)
                    e = fmax(e, fabs(out[j].p.v[q] - pool[i].T.p.v[q]));
                if (e < 1e-6) {
                    truth++;
                    break;
                }
            }
        }
        for (int r = 0; r < 9; r++) {
            double t0 = now_us();
            for (int i = 0; i < POOL; i++)
                solve(pool + i);
            t[r] = (now_us() - t0) / POOL;
            ts[r] = 0.0;
            if (sys < SFM_R2R_SYS_COUNT_) { /* the base solver alone on canonical input */
                const sfmi_r2r_system_desc *d = sfmi_r2r_table[sys];
                t0 = now_us();
                for (int i = 0; i < POOL; i++)
                    d->solve(pool[i].s, out, ws);
                ts[r] = (now_us() - t0) / POOL;
            }
        }
        qsort(t, 9, sizeof t[0], cmp);
        qsort(ts, 9, sizeof ts[0], cmp);
        char st[64] = "";
        if (fails)
            snprintf(st, sizeof st, "%ld of %d SFM_E_DEGENERATE", fails, POOL);
        if (sys < SFM_R2R_SYS_COUNT_)
            printf("%-11s %9.2f %9.2f %9.2f %7.1f%%  %s\n", names[sys], t[4], ts[4], (double)sols / POOL,
                   100.0 * truth / POOL, st);
        else
            printf("%-11s %9.2f %9s %9.2f %7.1f%%  %s\n", names[sys], t[4], "-", (double)sols / POOL,
                   100.0 * truth / POOL, st);
    }
    return 0;
}
