/*
 * Bare-metal Cortex-M7: relative poses from matched points that arrive as a
 * byte stream, by 5-point RANSAC in a static workspace (no heap, no OS).
 *
 * Stream (little endian; under emulation a host file opened through
 * semihosting, on a board any byte source: UART, SPI, a flash partition):
 *   "SFMM", uint32 version (1), uint32 problem count, then per problem
 *   uint32 n (5..MAXN), float64 fx fy cx cy, float64 R[9] t[3] (the true
 *   pose, x_cam2 = R x_cam1 + t, |t| = 1, for the error report; zeros when
 *   unknown), n x float64 (x1, y1, x2, y2) pixel matches.
 * Per problem it prints the pose (R row-major, t; x_cam2 = R x_cam1 + t),
 * the inliers, the iterations, the errors against the stream's truth and
 * the instructions the RANSAC call took: SysTick counts processor cycles,
 * and under `qemu-system-arm -icount shift=0` (one instruction per
 * nanosecond of virtual time, 25 MHz SysTick) a tick is 40 instructions.
 * Exit status (semihosting): 0 when every problem with a truth is within
 * 0.5 deg of rotation and 3 deg of translation direction.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm.h"

enum { MAXN = 512 };

static double px1[2 * MAXN], px2[2 * MAXN];
static uint8_t inliers[MAXN];
static unsigned char workspace[SFM_RANSAC_RELPOSE_WS_SIZE(MAXN)];

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define PI 3.14159265358979323846

static int rd(FILE *f, void *p, size_t n) { return fread(p, 1, n, f) == n; }

static int rd_u32(FILE *f, uint32_t *v)
{
    unsigned char b[4];
    if (!rd(f, b, 4))
        return 0;
    *v = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    return 1;
}

/* The target is little endian, as the stream: doubles are read as stored. */
static int rd_f64(FILE *f, double *v, int n) { return rd(f, v, sizeof(double) * (size_t)n); }

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

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "matches.bin";
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        printf("cannot open %s (semihosting file)\n", path);
        return 1;
    }
    char magic[4];
    uint32_t version, count;
    if (!rd(f, magic, 4) || memcmp(magic, "SFMM", 4) != 0 || !rd_u32(f, &version) || version != 1 ||
        !rd_u32(f, &count)) {
        printf("%s: not a version-1 SFMM stream: %s\n", path, sfm_status_str(SFM_E_FORMAT));
        fclose(f);
        return 1;
    }
    SYST_RVR = 0x00FFFFFFu;
    SYST_CVR = 0;
    SYST_CSR = 5u; /* enabled, processor clock, no interrupt */
    printf("libsfm %d relpose on cortex-m7: %u problems, static workspace %u bytes\n",
           sfm_version(), (unsigned)count, (unsigned)sizeof workspace);
    int bad = 0;
    for (uint32_t p = 0; p < count; p++) {
        uint32_t n;
        double k4[4], truth[12];
        if (!rd_u32(f, &n) || n < 5 || n > MAXN || !rd_f64(f, k4, 4) || !rd_f64(f, truth, 12)) {
            printf("problem %u: bad header: %s\n", (unsigned)p, sfm_status_str(SFM_E_FORMAT));
            fclose(f);
            return 1;
        }
        for (uint32_t i = 0; i < n; i++) {
            double m[4];
            if (!rd_f64(f, m, 4)) {
                printf("problem %u: stream ends early: %s\n", (unsigned)p, sfm_status_str(SFM_E_FORMAT));
                fclose(f);
                return 1;
            }
            px1[2 * i] = m[0];
            px1[2 * i + 1] = m[1];
            px2[2 * i] = m[2];
            px2[2 * i + 1] = m[3];
        }
        const sfm_camera cam = {SFM_CAMERA_PINHOLE, k4[0], k4[1], k4[2], k4[3], {0}};
        sfm_ransac_options opt;
        sfm_ransac_default_options(&opt);
        opt.threshold = 1.0;
        opt.min_iterations = 200;
        sfm_pose pose;
        sfm_ransac_stats st;
        size_t need = sfm_ransac_relpose_workspace_size((int)n);
        uint32_t t0 = SYST_CVR;
        int cnt = sfm_ransac_relpose(px1, px2, (int)n, &cam, &cam, &opt, &pose, NULL, inliers, &st,
                                     workspace, need);
        uint32_t t1 = SYST_CVR;
        uint32_t ticks = (t0 - t1) & 0x00FFFFFFu;
        if (cnt < 0) {
            printf("problem %u: relative pose failed: %s\n", (unsigned)p, sfm_status_str(cnt));
            bad++;
            continue;
        }
        printf("problem %u: %d matches, %d inliers, %d iterations, %lu SysTick ticks (%lu instructions under -icount shift=0)\n",
               (unsigned)p, (int)n, cnt, st.iterations, (unsigned long)ticks, 40ul * ticks);
        pfix("  R", pose.R, 9);
        pfix("  t", pose.t, 3);
        double tn = sqrt(truth[9] * truth[9] + truth[10] * truth[10] + truth[11] * truth[11]);
        if (tn > 0) {
            double ang = 0, dot = 0;
            sfm_rot_angle_between(pose.R, truth, &ang);
            for (int k = 0; k < 3; k++)
                dot += pose.t[k] * truth[9 + k] / tn;
            double tdir = acos(dot > 1 ? 1 : (dot < -1 ? -1 : dot));
            printf("  rotation error %d millideg, translation direction error %d millideg\n",
                   (int)(ang * 180e3 / PI), (int)(tdir * 180e3 / PI));
            if (!(ang < 0.5 * PI / 180 && tdir < 3.0 * PI / 180))
                bad++;
        }
    }
    fclose(f);
    return bad ? 1 : 0;
}
