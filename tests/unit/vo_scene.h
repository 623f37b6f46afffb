/* The synthetic sequence shared by the visual odometry tests: a 160 x 120
 * camera (f = 160 px, centred principal point) looking at a texture of 6 px
 * blocks of random gray (corners for FAST), its upper half a plane at depth
 * Z and its lower half a plane at 2 Z, so a sideways slide shifts the lower
 * half by half as many pixels (parallax). */
#ifndef SFM_TEST_VO_SCENE_H
#define SFM_TEST_VO_SCENE_H

#include <stdint.h>
#include <string.h>

#include "sfm/sfm_vo.h"
#include "sfm_test.h"

#define VO_SCENE_W 160
#define VO_SCENE_H 120
#define VO_SCENE_PAD 64 /* texture columns beyond the frame on each side */
#define VO_SCENE_NF 200
#define VO_SCENE_WIN 3
#define VO_SCENE_TEX_W (VO_SCENE_W + 2 * VO_SCENE_PAD)

/* Fills all VO_SCENE_H x VO_SCENE_TEX_W texels, block by block. */
static inline void vo_scene_texture(sfm_test_ctx *t, uint8_t *tex)
{
    const int tw = VO_SCENE_TEX_W;
    for (int by = 0; by < VO_SCENE_H; by += 6)
        for (int bx = 0; bx < tw; bx += 6) {
            int g = (int)sfm_test_uniform(t, 20, 235);
            for (int y = by; y < by + 6 && y < VO_SCENE_H; y++)
                for (int x = bx; x < bx + 6 && x < tw; x++)
                    tex[y * tw + x] = (uint8_t)g;
        }
}

/* A tightly packed frame: texture columns from base, the upper half shifted
 * by shift more, the lower half by shift / 2. */
static inline void vo_scene_crop(const uint8_t *tex, uint8_t *frame, int base, int shift)
{
    const int tw = VO_SCENE_TEX_W;
    for (int y = 0; y < VO_SCENE_H; y++) {
        int off = base + (y < VO_SCENE_H / 2 ? shift : shift / 2);
        memcpy(frame + y * VO_SCENE_W, tex + y * tw + off, VO_SCENE_W);
    }
}

/* The dimensions and the parameters the tests run with. */
static inline void vo_scene_setup(sfm_vo_dims *d, sfm_vo_params *p)
{
    d->width = VO_SCENE_W;
    d->height = VO_SCENE_H;
    d->max_features = VO_SCENE_NF;
    d->window = VO_SCENE_WIN;
    sfm_vo_default_params(d, p);
    p->camera.fx = p->camera.fy = 160.0;
    p->camera.cx = (VO_SCENE_W - 1) / 2.0;
    p->camera.cy = (VO_SCENE_H - 1) / 2.0;
    p->features.cell_size = 16;
    p->features.n_levels = 2;
    p->min_inliers = 12;
    p->init_radius = 40.0;
}

#endif
