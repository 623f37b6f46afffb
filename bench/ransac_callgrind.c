/*
 * Relative-pose RANSAC under callgrind: runs sfm_ransac_relpose on the
 * scenes of a file written by bench/ransac_callgrind.py (int32 scene count,
 * int32 n, float64 threshold in px, then per scene p1 and p2 as n x 2
 * float64), K = [[500,0,320],[0,500,240],[0,0,1]], seed = scene index,
 * confidence 0.999, at most 1000 samples (bench/ransac_bench.py's settings).
 * Prints one line per scene: index, status or inlier count, samples drawn.
 */
#include <stdio.h>
#include <stdlib.h>

#include "sfm/sfm_ransac.h"

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    FILE *f = fopen(argv[1], "rb");
    if (f == NULL)
        return 2;
    int ns, n;
    double thr;
    if (fread(&ns, 4, 1, f) != 1 || fread(&n, 4, 1, f) != 1 || fread(&thr, 8, 1, f) != 1)
        return 2;
    double *p1 = malloc(16 * (size_t)n), *p2 = malloc(16 * (size_t)n);
    size_t wsn = sfm_ransac_relpose_workspace_size(n);
    void *ws = malloc(wsn);
    if (p1 == NULL || p2 == NULL || ws == NULL)
        return 2;
    const sfm_camera cam = {SFM_CAMERA_PINHOLE, 500.0, 500.0, 320.0, 240.0, {0, 0, 0, 0, 0}};
    for (int k = 0; k < ns; k++) {
        if (fread(p1, 16, (size_t)n, f) != (size_t)n || fread(p2, 16, (size_t)n, f) != (size_t)n)
            return 2;
        sfm_ransac_options o;
        sfm_ransac_default_options(&o);
        o.threshold = thr;
        o.seed = (uint64_t)k;
        o.confidence = 0.999;
        o.max_iterations = 1000;
        sfm_pose pose;
        sfm_ransac_stats st;
        int r = sfm_ransac_relpose(p1, p2, n, &cam, &cam, &o, &pose, NULL, NULL, &st, ws, wsn);
        printf("%d %d %d\n", k, r, r > 0 ? st.iterations : 0);
    }
    fclose(f);
    free(p1);
    free(p2);
    free(ws);
    return 0;
}
