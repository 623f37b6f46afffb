/*
 * One dense-stereo call on a raw 8-bit gray pair, for instruction counts
 * under callgrind (repeatable, unlike wall time on a shared machine).
 * Usage: stereo_callgrind block|sgm5|sgm8 left.raw right.raw width height [disp.f32]
 * 64 disparities, default options otherwise; prints the valid count and an
 * FNV-1a hash of the disparity bytes, and writes them when asked.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_stereo.h"

static uint8_t *read_raw(const char *path, size_t n)
{
    uint8_t *p = malloc(n);
    FILE *f = fopen(path, "rb");
    if (p == NULL || f == NULL || fread(p, 1, n, f) != n) {
        fprintf(stderr, "cannot read %s\n", path);
        exit(1);
    }
    fclose(f);
    return p;
}

int main(int argc, char **argv)
{
    if (argc != 6 && argc != 7) {
        fprintf(stderr, "usage: %s block|sgm5|sgm8 left.raw right.raw width height [disp.f32]\n",
                argv[0]);
        return 2;
    }
    const int w = atoi(argv[4]), h = atoi(argv[5]);
    if (w < 1 || h < 1) {
        fprintf(stderr, "bad size\n");
        return 2;
    }
    const size_t n = (size_t)w * (size_t)h;
    uint8_t *L = read_raw(argv[2], n), *R = read_raw(argv[3], n);
    float *disp = malloc(sizeof(float) * n);
    size_t need;
    void *ws;
    int r;
    if (strcmp(argv[1], "block") == 0) {
        sfm_stereo_block_options o;
        sfm_stereo_block_default_options(&o);
        need = sfm_stereo_block_workspace_size(w, h, &o);
        ws = malloc(need);
        r = sfm_stereo_block(L, R, w, h, w, &o, disp, ws, need);
    } else {
        sfm_stereo_sgm_options o;
        sfm_stereo_sgm_default_options(&o);
        o.paths = strcmp(argv[1], "sgm8") == 0 ? 8 : 5;
        need = sfm_stereo_sgm_workspace_size(w, h, &o);
        ws = malloc(need);
        r = sfm_stereo_sgm(L, R, w, h, w, &o, disp, ws, need);
    }
    uint64_t hash = 1469598103934665603ull;
    const uint8_t *b = (const uint8_t *)disp;
    for (size_t i = 0; i < sizeof(float) * n; i++)
        hash = (hash ^ b[i]) * 1099511628211ull;
    printf("%s: %d valid, workspace %zu bytes, hash %016llx\n", argv[1], r, need,
           (unsigned long long)hash);
    if (argc == 7) {
        FILE *f = fopen(argv[6], "wb");
        if (f == NULL || fwrite(disp, sizeof(float), n, f) != n)
            return 1;
        fclose(f);
    }
    free(L);
    free(R);
    free(disp);
    free(ws);
    return r < 0;
}
