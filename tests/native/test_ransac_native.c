/* RANSAC estimators, host-only: large synthetic problems, two threads at
 * once, and real matches with metric ground truth (Herz-Jesu-P8). */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../unit/ransac_scene.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

#define NB 1000

SFM_TEST(ransac_native_relpose_large_outlier_levels)
{
    const double ratios[3] = {0.25, 0.5, 0.75};
    sfm_camera cam = scene_pinhole();
    static double p1[2 * NB], p2[2 * NB];
    static unsigned char truth[NB];
    static uint8_t m1[NB], m2[NB];
    size_t wsn = sfm_ransac_relpose_workspace_size(NB);
    unsigned char *ws = malloc(wsn);
    for (int r = 0; r < 3; r++) {
        double er[10], et[10];
        for (int k = 0; k < 10; k++) {
            double R[9], tr[3];
            scene_twoview(t, &cam, NB, ratios[r], 1.0, 0, p1, p2, truth, R, tr);
            sfm_ransac_options opt;
            sfm_ransac_default_options(&opt);
            /* 1 px noise: a 1.5 px threshold keeps ~70 % of the inliers; at
             * 75 % outliers a good sample is then ~1 in 6000 */
            opt.threshold = 1.5;
            opt.max_iterations = 20000;
            opt.seed = 1000u + (uint64_t)k;
            sfm_pose a, b;
            int na = sfm_ransac_relpose(p1, p2, NB, &cam, &cam, &opt, &a, NULL, m1, NULL, ws, wsn);
            int nb = sfm_ransac_relpose(p1, p2, NB, &cam, &cam, &opt, &b, NULL, m2, NULL, ws, wsn);
            SFM_CHECK(na > 0 && na == nb);
            SFM_CHECK(memcmp(m1, m2, sizeof m1) == 0);
            SFM_CHECK(memcmp(&a, &b, sizeof a) == 0);
            er[k] = na > 0 ? scene_rot_err_deg(a.R, R) : 180;
            et[k] = na > 0 ? scene_dir_err_deg(a.t, tr) : 180;
        }
        double mr = scene_median(er, 10), mt = scene_median(et, 10);
        SFM_TEST_LOG("N=%d outliers %.0f%% thr 1.5px: median rotation %.3f deg, translation %.3f deg",
                     NB, 100 * ratios[r], mr, mt);
        SFM_CHECK(mr < 0.3);
        SFM_CHECK(mt < 1.5);
    }
    free(ws);
}

/* The hardest benchmark setting: 75 % outliers, 1 px noise, a 1 px
 * threshold and at most 1000 samples, where a clean sample turns up about
 * once per run (probability 0.62) and its noisy model usually fits only part
 * of the inliers. A run succeeds when its rotation is within 1 degree and
 * its translation direction within 5 degrees of the truth. Before the LO's
 * inner RANSAC (and the other changes that came with it) 20 (N = 200) and
 * 23 (N = 1000) of these 40 scenes succeeded; with it, 27 and 39. */
SFM_TEST(ransac_native_relpose_75_percent_outliers_1px_threshold)
{
    const int sizes[2] = {200, NB};
    sfm_camera cam = scene_pinhole();
    static double p1[2 * NB], p2[2 * NB];
    static unsigned char truth[NB];
    size_t wsn = sfm_ransac_relpose_workspace_size(NB);
    unsigned char *ws = malloc(wsn);
    for (int s = 0; s < 2; s++) {
        enum { TRIALS = 40 };
        double er[TRIALS];
        int n = sizes[s], ok = 0;
        for (int k = 0; k < TRIALS; k++) {
            double R[9], tr[3];
            scene_twoview(t, &cam, n, 0.75, 1.0, 0, p1, p2, truth, R, tr);
            sfm_ransac_options opt;
            sfm_ransac_default_options(&opt);
            opt.threshold = 1.0;
            opt.max_iterations = 1000;
            opt.seed = (uint64_t)k;
            sfm_pose a;
            int na = sfm_ransac_relpose(p1, p2, n, &cam, &cam, &opt, &a, NULL, NULL, NULL, ws, wsn);
            er[k] = na > 0 ? scene_rot_err_deg(a.R, R) : 180;
            ok += na > 0 && er[k] < 1.0 && scene_dir_err_deg(a.t, tr) < 5.0;
        }
        double mr = scene_median(er, TRIALS);
        SFM_TEST_LOG("N=%d outliers 75%% thr 1px, 1000 samples: %d of %d succeed, median "
                     "rotation error %.3f deg", n, ok, TRIALS, mr);
        SFM_CHECK(ok >= (n == NB ? 33 : 23));
    }
    free(ws);
}

typedef struct job {
    double p1[2 * NB], p2[2 * NB];
    uint64_t seed;
    sfm_pose pose;
    uint8_t mask[NB];
    int ret;
    unsigned char *ws;
    size_t wsn;
} job;

static void *run_job(void *arg)
{
    job *j = arg;
    sfm_camera cam = scene_pinhole();
    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.seed = j->seed;
    opt.max_iterations = 1000;
    j->ret = sfm_ransac_relpose(j->p1, j->p2, NB, &cam, &cam, &opt, &j->pose, NULL, j->mask, NULL,
                                j->ws, j->wsn);
    return NULL;
}

SFM_TEST(ransac_native_two_threads_match_alone)
{
    sfm_camera cam = scene_pinhole();
    static job jobs[2], alone[2];
    static unsigned char truth[NB];
    size_t wsn = sfm_ransac_relpose_workspace_size(NB);
    for (int k = 0; k < 2; k++) {
        double R[9], tr[3];
        scene_twoview(t, &cam, NB, 0.5, 1.0, 0, jobs[k].p1, jobs[k].p2, truth, R, tr);
        jobs[k].seed = 5u + (uint64_t)k;
        jobs[k].ws = malloc(wsn);
        jobs[k].wsn = wsn;
        alone[k] = jobs[k];
        run_job(&alone[k]);
    }
    for (int rep = 0; rep < 3; rep++) {
        pthread_t th[2];
        for (int k = 0; k < 2; k++)
            pthread_create(&th[k], NULL, run_job, &jobs[k]);
        for (int k = 0; k < 2; k++)
            pthread_join(th[k], NULL);
        for (int k = 0; k < 2; k++) {
            SFM_CHECK(jobs[k].ret > 0);
            SFM_CHECK_EQ_INT(jobs[k].ret, alone[k].ret);
            SFM_CHECK(memcmp(&jobs[k].pose, &alone[k].pose, sizeof(sfm_pose)) == 0);
            SFM_CHECK(memcmp(jobs[k].mask, alone[k].mask, NB) == 0);
        }
    }
    free(jobs[0].ws);
    free(jobs[1].ws);
}

/* ---- Herz-Jesu-P8 ------------------------------------------------------ */

#define HJ "../shared/data/herzjesu-p8"

typedef struct hj_cam {
    double K[9], Rcw[9], C[3]; /* Rcw: camera-to-world (file convention) */
} hj_cam;

static int read_camera(int v, hj_cam *c)
{
    char path[256];
    snprintf(path, sizeof path, HJ "/gt_dense_cameras/%04d.jpg.camera", v);
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    double d[3];
    int ok = 1;
    for (int i = 0; i < 9; i++)
        ok &= fscanf(f, "%lf", &c->K[i]) == 1;
    for (int i = 0; i < 3; i++)
        ok &= fscanf(f, "%lf", &d[i]) == 1;
    for (int i = 0; i < 9; i++)
        ok &= fscanf(f, "%lf", &c->Rcw[i]) == 1;
    for (int i = 0; i < 3; i++)
        ok &= fscanf(f, "%lf", &c->C[i]) == 1;
    fclose(f);
    return ok;
}

/* Reads rows x1 y1 x2 y2 x3 y3; returns the row count (at most cap). */
static int read_triplet(const char *path, double *rows, int cap)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[512];
    int n = 0;
    while (n < cap && fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        double *r = rows + 6 * n;
        if (sscanf(line, "%lf %lf %lf %lf %lf %lf", r, r + 1, r + 2, r + 3, r + 4, r + 5) == 6)
            n++;
    }
    fclose(f);
    return n;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

SFM_TEST(ransac_native_herzjesu_relpose_vs_ground_truth)
{
    hj_cam cams[8];
    for (int v = 0; v < 8; v++) {
        if (!read_camera(v, &cams[v])) {
            printf("SKIP: " HJ " not found; Herz-Jesu-P8 relative pose test skipped\n");
            return;
        }
    }
    enum { CAP = 2000, MAXPAIRS = 200 };
    static double rows[6 * CAP], p1[2 * CAP], p2[2 * CAP];
    static double er[MAXPAIRS], et[MAXPAIRS], fin[MAXPAIRS];
    int npairs = 0;
    size_t wsn = sfm_ransac_relpose_workspace_size(CAP);
    unsigned char *ws = malloc(wsn);
    for (int a = 0; a < 8; a++)
        for (int b = a + 1; b < 8; b++)
            for (int c = b + 1; c < 8; c++) {
                char path[256];
                snprintf(path, sizeof path, HJ "/triplets/triplet_%04d_%04d_%04d.txt", a, b, c);
                int n = read_triplet(path, rows, CAP);
                if (n < 0) {
                    printf("SKIP: %s missing\n", path);
                    free(ws);
                    return;
                }
                /* one pair per triplet file: its first two views */
                if (n < 30 || npairs >= MAXPAIRS)
                    continue;
                for (int i = 0; i < n; i++) {
                    p1[2 * i] = rows[6 * i];
                    p1[2 * i + 1] = rows[6 * i + 1];
                    p2[2 * i] = rows[6 * i + 2];
                    p2[2 * i + 1] = rows[6 * i + 3];
                }
                sfm_camera c1, c2;
                memset(&c1, 0, sizeof c1);
                memset(&c2, 0, sizeof c2);
                c1.model = c2.model = SFM_CAMERA_PINHOLE;
                c1.fx = cams[a].K[0], c1.fy = cams[a].K[4], c1.cx = cams[a].K[2], c1.cy = cams[a].K[5];
                c2.fx = cams[b].K[0], c2.fy = cams[b].K[4], c2.cx = cams[b].K[2], c2.cy = cams[b].K[5];
                sfm_ransac_options opt;
                sfm_ransac_default_options(&opt);
                opt.threshold = 1.0;
                sfm_pose pose;
                sfm_ransac_stats st;
                int ni = sfm_ransac_relpose(p1, p2, n, &c1, &c2, &opt, &pose, NULL, NULL, &st, ws, wsn);
                SFM_CHECK(ni > 0);
                /* truth: x2 = R2^T R1 x1 + R2^T (C1 - C2) with R_i camera-to-world */
                double Rg[9], tg[3], dC[3];
                const double *R1 = cams[a].Rcw, *R2 = cams[b].Rcw;
                for (int r = 0; r < 3; r++)
                    for (int k = 0; k < 3; k++)
                        Rg[3 * r + k] = R2[r] * R1[k] + R2[3 + r] * R1[3 + k] + R2[6 + r] * R1[6 + k];
                for (int k = 0; k < 3; k++)
                    dC[k] = cams[a].C[k] - cams[b].C[k];
                for (int r = 0; r < 3; r++)
                    tg[r] = R2[r] * dC[0] + R2[3 + r] * dC[1] + R2[6 + r] * dC[2];
                er[npairs] = ni > 0 ? scene_rot_err_deg(pose.R, Rg) : 180;
                et[npairs] = ni > 0 ? scene_dir_err_deg(pose.t, tg) : 180;
                fin[npairs] = (double)ni / n;
                npairs++;
            }
    free(ws);
    SFM_CHECK(npairs >= 40);
    qsort(er, (size_t)npairs, sizeof(double), cmp_double);
    qsort(et, (size_t)npairs, sizeof(double), cmp_double);
    qsort(fin, (size_t)npairs, sizeof(double), cmp_double);
    double mr = er[npairs / 2], mt = et[npairs / 2];
    SFM_TEST_LOG("Herz-Jesu-P8, %d view pairs, 1 px: median rotation error %.3f deg, translation "
                 "direction %.3f deg (90th pct %.3f / %.3f), median inlier fraction %.2f",
                 npairs, mr, mt, er[npairs * 9 / 10], et[npairs * 9 / 10], fin[npairs / 2]);
    SFM_CHECK(mr < 0.2);
    SFM_CHECK(mt < 1.0);
}
