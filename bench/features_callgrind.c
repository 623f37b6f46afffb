/*
 * One sfm_features_detect call (default parameters) on a raw 8-bit gray
 * image, for instruction counts under callgrind (repeatable, unlike wall
 * time on a shared machine). Usage: features_callgrind image.raw width height
 */
#include <stdio.h>
#include <stdlib.h>

#include "sfm/sfm_features.h"

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: %s image.raw width height\n", argv[0]);
        return 2;
    }
    const int w = atoi(argv[2]), h = atoi(argv[3]);
    if (w < 1 || h < 1) {
        fprintf(stderr, "bad size\n");
        return 2;
    }
    uint8_t *img = malloc((size_t)w * (size_t)h);
    FILE *f = fopen(argv[1], "rb");
    if (img == NULL || f == NULL || fread(img, 1, (size_t)w * (size_t)h, f) != (size_t)w * (size_t)h) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    fclose(f);
    sfm_features_params p;
    sfm_features_default_params(&p);
    const size_t need = sfm_features_workspace_size(&p, w, h);
    void *ws = malloc(need);
    sfm_keypoint *kps = malloc(sizeof(sfm_keypoint) * (size_t)p.max_features);
    uint8_t *desc = malloc((size_t)SFM_FEATURES_DESC_BYTES * (size_t)p.max_features);
    sfm_image_u8 im = {img, w, h, w};
    int n = sfm_features_detect(&im, &p, kps, desc, p.max_features, ws, need);
    printf("%d keypoints, workspace %zu bytes\n", n, need);
    free(img);
    free(ws);
    free(kps);
    free(desc);
    return n < 0;
}
