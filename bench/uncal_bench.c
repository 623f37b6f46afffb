/*
 * Uncalibrated three-view reconstruction from matches: time per triplet of
 * sfm_recon_three_view_uncalibrated on the Herz-Jesu-P8 match triplets
 * (../shared/data/herzjesu-p8/triplets, or the directory given), beside the
 * trifocal RANSAC alone on the same input (the share of the metric stage is
 * the difference) and the pipeline with the pinhole model (options.radial
 * 0) on it: the cost of the two radial terms is the ratio. Anchor: BoofCV 1.2.2 takes 1.2 s per triplet (0.67 s in
 * its reconstruction call) on the same triplets (make bench-uncal-boofcv runs it
 * beside this bench on this machine). One run; timings vary with
 * the load of the machine and are never asserted.
 * `uncal_bench DIR LINES` (LINES a comma list of the index's data lines,
 * 1-based) runs only the default pipeline on those triplets, once each, for
 * callgrind (bench/uncal_callgrind.sh counts its instructions per triplet).
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sfm/sfm.h"

#define MAXN 4000

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double px[3][2 * MAXN];

/* Whether k is in the comma list s. */
static int listed(const char *s, int k)
{
    while (*s) {
        char *end;
        long v = strtol(s, &end, 10);
        if (end == s)
            return 0;
        if (v == k)
            return 1;
        s = *end == ',' ? end + 1 : end;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "../shared/data/herzjesu-p8/triplets";
    const char *lines = argc > 2 ? argv[2] : NULL;
    char path[1024];
    snprintf(path, sizeof path, "%s/triplets_index.txt", dir);
    FILE *idx = fopen(path, "r");
    if (!idx) {
        printf("SKIP: %s not found\n", path);
        return 0;
    }
    size_t need = sfm_recon_three_view_uncalibrated_workspace_size(MAXN);
    size_t need_r = sfm_ransac_trifocal_workspace_size(MAXN);
    void *ws = malloc(need > need_r ? need : need_r);
    double t_all[128], t_ran[128], t_pin[128];
    int nt = 0, ok = 0, within = 0, ok_pin = 0, data_line = 0;
    char line[256];
    while (fgets(line, sizeof line, idx) && nt < 128) {
        char a[16], b[16], c[16];
        if (line[0] == '#' || sscanf(line, "%15s %15s %15s", a, b, c) != 3)
            continue;
        data_line++;
        if (lines != NULL && !listed(lines, data_line))
            continue;
        snprintf(path, sizeof path, "%s/triplet_%s_%s_%s.txt", dir, a, b, c);
        FILE *f = fopen(path, "r");
        if (!f)
            continue;
        int n = 0;
        char l2[512];
        while (fgets(l2, sizeof l2, f) && n < MAXN) {
            double v[6];
            if (l2[0] == '#' || sscanf(l2, "%lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]) != 6)
                continue;
            for (int k = 0; k < 3; k++) {
                px[k][2 * n] = v[2 * k];
                px[k][2 * n + 1] = v[2 * k + 1];
            }
            n++;
        }
        fclose(f);
        sfm_uncal_options o;
        sfm_uncal_default_options(&o);
        o.ransac.seed = 1;
        double K[27];
        sfm_pose poses[3];
        sfm_uncal_report rep;
        double t0 = now_ms();
        int st = sfm_recon_three_view_uncalibrated(px[0], px[1], px[2], n, 3072, 2048, &o, K, poses, NULL, NULL,
                                                   &rep, ws, need);
        double t1 = now_ms();
        if (lines != NULL) {
            printf("%s %s %s  n %4d  %s  f %7.1f  runs %d\n", a, b, c, n, st > 0 ? "ok  " : "fail",
                   st > 0 ? K[0] : 0.0, rep.attempts);
            continue;
        }
        sfm_uncal_options op = o;
        op.radial = 0;
        double Kp[27];
        sfm_uncal_report repp;
        double tp0 = now_ms();
        int stp = sfm_recon_three_view_uncalibrated(px[0], px[1], px[2], n, 3072, 2048, &op, Kp, poses, NULL,
                                                    NULL, &repp, ws, need);
        double tp1 = now_ms();
        ok_pin += stp > 0;
        t_pin[nt] = tp1 - tp0;
        double T[27];
        /* RANSAC alone, on the centred pixels the pipeline gives it */
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < n; i++) {
                px[k][2 * i] -= 1535.5;
                px[k][2 * i + 1] -= 1023.5;
            }
        double t2 = now_ms();
        sfm_ransac_trifocal(px[0], px[1], px[2], n, &o.ransac, T, NULL, NULL, NULL, ws, need_r);
        double t3 = now_ms();
        t_all[nt] = t1 - t0;
        t_ran[nt] = t3 - t2;
        ok += st > 0;
        within += st > 0 && K[0] > 0.95 * 2759.48 && K[0] < 1.05 * 2759.48;
        printf("%s %s %s  n %4d  %s  f %7.1f  runs %d  total %7.1f ms  (pinhole %7.1f ms, RANSAC alone %7.1f ms)\n",
               a, b, c, n, st > 0 ? "ok  " : "fail", st > 0 ? K[0] : 0.0, rep.attempts, t1 - t0, tp1 - tp0,
               t3 - t2);
        nt++;
    }
    fclose(idx);
    if (lines != NULL) {
        free(ws);
        return 0;
    }
    double s_all[128], s_ran[128], s_pin[128], sum = 0;
    memcpy(s_all, t_all, sizeof(double) * nt);
    memcpy(s_ran, t_ran, sizeof(double) * nt);
    memcpy(s_pin, t_pin, sizeof(double) * nt);
    qsort(s_all, nt, sizeof(double), cmp);
    qsort(s_ran, nt, sizeof(double), cmp);
    qsort(s_pin, nt, sizeof(double), cmp);
    for (int i = 0; i < nt; i++)
        sum += t_all[i];
    printf("uncalibrated three-view, %d Herz-Jesu-P8 triplets: %d answered, %d within 5 %% of f; "
           "median %.1f ms per triplet (RANSAC alone %.1f ms), mean %.1f ms; BoofCV 1.2.2: 1200 ms\n",
           nt, ok, within, s_all[nt / 2], s_ran[nt / 2], sum / nt);
    printf("pinhole model (radial 0) on the same triplets: %d answered, median %.1f ms; median ratio "
           "radial / pinhole %.2f\n", ok_pin, s_pin[nt / 2], s_pin[nt / 2] > 0 ? s_all[nt / 2] / s_pin[nt / 2] : 0.0);
    free(ws);
    return 0;
}
