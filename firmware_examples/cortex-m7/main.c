/*
 * libsfm on a Cortex-M7 with no heap: relative pose of a camera between two
 * frames from 100 point matches, 20% of them wrong, by 5-point RANSAC.
 * Every buffer is static, the workspace sized at compile time by
 * SFM_RANSAC_RELPOSE_WS_SIZE and checked against the library's own
 * workspace-size function at start-up. Build: `make firmware`; run under
 * emulation: see the README (the same image runs on an MPS2 AN500 board).
 *
 * relpose_demo.ld gives it 64 KB of flash and 32 KB of RAM; at the end it
 * prints what it used of that RAM (data + bss, heap, deepest stack), the
 * stack measured by filling the free RAM with a pattern first.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "sfm/sfm.h"

enum { N = 100 };

static double px1[2 * N], px2[2 * N];
static uint8_t inliers[N];
static unsigned char workspace[SFM_RANSAC_RELPOSE_WS_SIZE(N)];

/* Linker-script symbols: start of data, end of bss (= start of the heap),
 * top of the stack. */
extern uint32_t __data_start, __stack_top;
extern char end;
extern void *sbrk(ptrdiff_t increment); /* newlib's, hidden by -std=c11 */
#define PAINT 0x5AA5C33Cu

/* Fills the RAM between the heap's end and (a margin below) this frame. */
static void __attribute__((noinline)) paint_free_ram(void)
{
    volatile unsigned *p = (volatile unsigned *)(((unsigned)sbrk(0) + 259u) & ~3u);
    volatile unsigned *stop = (volatile unsigned *)((unsigned)__builtin_frame_address(0) - 64u);
    while (p < stop)
        *p++ = PAINT;
}

/* The lowest address the stack reached: the first overwritten word above
 * the heap's end. */
static unsigned stack_low_water(void)
{
    const unsigned *p = (const unsigned *)(((unsigned)sbrk(0) + 259u) & ~3u);
    while (p < (const unsigned *)&__stack_top && *p == PAINT)
        p++;
    return (unsigned)p;
}

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    paint_free_ram();
    const sfm_camera cam = {SFM_CAMERA_PINHOLE, 500, 500, 320, 240, {0}};
    size_t need = sfm_ransac_relpose_workspace_size(N);
    if (need == 0 || need > sizeof workspace) { /* cannot happen: the macro bounds the function */
        printf("workspace: need %u bytes, have %u\n", (unsigned)need, (unsigned)sizeof workspace);
        return 1;
    }

    /* Ground truth: 5 degrees of yaw and a step sideways and forward. */
    const double aa[3] = {0.0, 5.0 * 3.14159265358979 / 180.0, 0.0};
    sfm_pose truth = {{0}, {0.8, 0.0, 0.6}};
    sfm_rot_from_axis_angle(aa, truth.R);
    sfm_rng rng;
    sfm_rng_seed(&rng, SFM_RNG_DEFAULT_SEED);
    for (int i = 0; i < N; i++) {
        double X[3] = {4 * sfm_rng_uniform(&rng) - 2, 3 * sfm_rng_uniform(&rng) - 1.5,
                       4 + 6 * sfm_rng_uniform(&rng)};
        double Y[3];
        for (int r = 0; r < 3; r++)
            Y[r] = truth.R[3 * r] * X[0] + truth.R[3 * r + 1] * X[1] + truth.R[3 * r + 2] * X[2] + truth.t[r];
        sfm_camera_project(&cam, X, &px1[2 * i], NULL);
        sfm_camera_project(&cam, Y, &px2[2 * i], NULL);
        for (int k = 0; k < 2; k++)
            px2[2 * i + k] += 0.5 * sfm_rng_normal(&rng);
        if (i % 5 == 0) { /* a wrong match */
            px2[2 * i] = 640 * sfm_rng_uniform(&rng);
            px2[2 * i + 1] = 480 * sfm_rng_uniform(&rng);
        }
    }

    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 1.5;
    sfm_pose pose;
    sfm_ransac_stats stats;
    int cnt = sfm_ransac_relpose(px1, px2, N, &cam, &cam, &opt, &pose, NULL, inliers, &stats,
                                 workspace, need);
    if (cnt < 0) {
        printf("relative pose failed: %s\n", sfm_status_str(cnt));
        return 1;
    }
    double angle = 0, dot = 0;
    sfm_rot_angle_between(pose.R, truth.R, &angle);
    for (int k = 0; k < 3; k++)
        dot += pose.t[k] * truth.t[k];
    double tdir = acos(dot > 1 ? 1 : dot);
    /* Printed as integers: newlib's nano printf has no %f. */
    printf("libsfm %d on cortex-m7: %d inliers of %d, %d iterations, workspace %u bytes\n",
           sfm_version(), cnt, N, stats.iterations, (unsigned)need);
    printf("rotation error %d millideg, translation direction error %d millideg\n",
           (int)(angle * 180e3 / 3.14159265358979), (int)(tdir * 180e3 / 3.14159265358979));
    unsigned top = (unsigned)&__stack_top, low = stack_low_water();
    unsigned statics = (unsigned)&end - (unsigned)&__data_start;
    unsigned heap = (unsigned)sbrk(0) - (unsigned)&end;
    printf("ram: %u bytes (data+bss %u, heap %u, stack %u) of %u\n", statics + heap + (top - low), statics,
           heap, top - low, top - (unsigned)&__data_start);
    return angle < 0.5 * 3.14159265358979 / 180 && tdir < 3.0 * 3.14159265358979 / 180 ? 0 : 1;
}
