/*
 * Trifocal benchmark: sfm_trifocal_7pt on 7 triplets, and sfm_ransac_trifocal
 * on 500 and 2000 triplets with 30% outliers (0.5 px noise, threshold 1.5 px),
 * CPU time per call (median of repeats), iterations and inliers found.
 * No anchor exists in the pip-installable libraries (neither PoseLib nor
 * OpenCV has a trifocal estimator), so the figures stand alone.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sfm/sfm.h"
#include "trifocal_scene.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}


static void scene(sfm_rng *r, int n, double outliers, double *x1, double *x2, double *x3)
{
    double P[3][12];
    for (int v = 0; v < 3; v++)
        camera(r, P[v]);
    for (int i = 0; i < n;) {
        double X[3] = {6 * sfm_rng_uniform(r) - 3, 4 * sfm_rng_uniform(r) - 2, 5 + 5 * sfm_rng_uniform(r)};
        double *xs[3] = {&x1[2 * i], &x2[2 * i], &x3[2 * i]};
        if (!project(P[0], X, xs[0]) || !project(P[1], X, xs[1]) || !project(P[2], X, xs[2]))
            continue;
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 2; k++)
                xs[v][k] += 0.5 * sfm_rng_normal(r);
        if (sfm_rng_uniform(r) < outliers) {
            xs[2][0] = 640 * sfm_rng_uniform(r);
            xs[2][1] = 480 * sfm_rng_uniform(r);
        }
        i++;
    }
}

int main(void)
{
    enum { NMAX = 2000, REPS = 15 };
    static double x1[2 * NMAX], x2[2 * NMAX], x3[2 * NMAX];
    static double times[1000];
    sfm_rng r;
    sfm_rng_seed(&r, 2024);

    /* trifocal_7pt: 1000 different 7-triplet problems */
    size_t ws7 = sfm_trifocal_7pt_workspace_size();
    void *w7 = malloc(ws7);
    double T[27];
    double y1[14 * 1000], y2[14 * 1000], y3[14 * 1000];
    for (int p = 0; p < 1000; p++)
        scene(&r, 7, 0.0, &y1[14 * p], &y2[14 * p], &y3[14 * p]);
    for (int rep = 0; rep < REPS; rep++) {
        double t0 = cpu_now();
        for (int p = 0; p < 1000; p++)
            sfm_trifocal_7pt(&y1[14 * p], &y2[14 * p], &y3[14 * p], 7, T, w7, ws7);
        times[rep] = (cpu_now() - t0) / 1000;
    }
    qsort(times, REPS, sizeof(double), cmp);
    printf("trifocal_7pt (7 triplets, linear + algebraic minimization): %.1f us/call\n", 1e6 * times[REPS / 2]);
    free(w7);

    const int sizes[2] = {500, 2000};
    for (int s = 0; s < 2; s++) {
        int n = sizes[s];
        scene(&r, n, 0.3, x1, x2, x3);
        size_t need = sfm_ransac_trifocal_workspace_size(n);
        void *ws = malloc(need);
        sfm_ransac_options opt;
        sfm_ransac_default_options(&opt);
        opt.threshold = 1.5;
        sfm_ransac_stats st;
        int cnt = 0, reps = 7;
        for (int rep = 0; rep < reps; rep++) {
            double t0 = cpu_now();
            cnt = sfm_ransac_trifocal(x1, x2, x3, n, &opt, T, NULL, NULL, &st, ws, need);
            times[rep] = cpu_now() - t0;
        }
        qsort(times, (size_t)reps, sizeof(double), cmp);
        printf("estimate_trifocal n=%d, 30%% outliers: %.1f ms/call, %d iterations, %d inliers, %d LO runs, "
               "workspace %zu bytes\n", n, 1e3 * times[reps / 2], st.iterations, cnt, st.lo_runs, need);
        free(ws);
    }
    return 0;
}
