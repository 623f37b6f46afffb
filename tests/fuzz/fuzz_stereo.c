/* Fuzz target: the stereo entry points. The first byte picks one:
 *   0 sfm_stereo_rectify (two cameras, R, t, alpha and output sizes as raw
 *     doubles / bytes: NaN, infinities, 1e300, coincident centres) and, on
 *     success, sfm_stereo_rectify_map of view 1 into an exact-size block;
 *   1 sfm_stereo_remap (source 1x1..40x40 with stride padding, a map of raw
 *     int32 entries, destination with a guard band);
 *   2 sfm_stereo_sgm and 3 sfm_stereo_block (16..40 pixels a side, options
 *     from the input in and out of range, exact-size workspace).
 * Any input gives a status; on failure the outputs keep their canary; on
 * success the remap writes inside its rows only and every disparity is NaN
 * or within the searched range. Buffers are exact-size heap blocks, so a
 * read or write past one is an ASan report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_stereo.h"

#include "fuzz_reader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void camera(reader *r, sfm_camera *c)
{
    memset(c, 0, sizeof *c);
    c->model = (int)(take_u8(r) % 4);
    c->fx = take_f64(r);
    c->fy = take_f64(r);
    c->cx = take_f64(r);
    c->cy = take_f64(r);
    for (int i = 0; i < 5; i++)
        c->dist[i] = take_u8(r) & 1 ? take_f64(r) : 0.0;
}

static void op_rectify(reader *r)
{
    sfm_camera c1, c2;
    camera(r, &c1);
    camera(r, &c2);
    double R[9], t[3];
    for (int i = 0; i < 9; i++)
        R[i] = take_f64(r);
    for (int i = 0; i < 3; i++)
        t[i] = take_f64(r);
    double alpha = take_f64(r);
    int w = (int)(take_u8(r) % 64), h = (int)(take_u8(r) % 64);
    int ow = (int)(take_u8(r) % 64) - 8, oh = (int)(take_u8(r) % 64) - 8;
    sfm_stereo_rectification out, canary;
    memset(&canary, 0x5a, sizeof canary);
    out = canary;
    int st = sfm_stereo_rectify(&c1, &c2, w, h, R, t, alpha, ow, oh, &out);
    if (st != SFM_OK) {
        if (memcmp(&out, &canary, sizeof out) != 0)
            abort();
        if (st != SFM_E_ARGUMENT && st != SFM_E_NONFINITE && st != SFM_E_SINGULAR)
            abort();
        return;
    }
    if (out.width < 1 || out.height < 1 || !(out.baseline > 0.0))
        abort();
    size_t n = 2u * (size_t)out.width * (size_t)out.height;
    int32_t *map = malloc(n * sizeof *map);
    if (map == NULL)
        return;
    st = sfm_stereo_rectify_map(&c1, w, h, &out, 1, map, n);
    if (st != SFM_OK && st != SFM_E_NONFINITE && st != SFM_E_ARGUMENT)
        abort();
    free(map);
}

static void op_remap(reader *r)
{
    int sw = (int)(take_u8(r) % 40) + 1, sh = (int)(take_u8(r) % 40) + 1, pad = (int)(take_u8(r) % 4);
    int ow = (int)(take_u8(r) % 20), oh = (int)(take_u8(r) % 20), dpad = (int)(take_u8(r) % 4);
    int ss = sw + pad - (int)(take_u8(r) % 2); /* sometimes one short of the width */
    size_t sn = (size_t)(ss > 0 ? ss : 1) * (size_t)(sh - 1) + (size_t)sw;
    uint8_t *src = malloc(sn);
    int32_t *map = malloc(2u * (size_t)(ow ? ow : 1) * (size_t)(oh ? oh : 1) * sizeof *map);
    int ds = ow + dpad;
    size_t dn = (size_t)(ds ? ds : 1) * (size_t)(oh ? oh : 1) + 16;
    uint8_t *dst = malloc(dn);
    if (src && map && dst) {
        for (size_t i = 0; i < sn; i++)
            src[i] = (uint8_t)take_u8(r);
        for (size_t i = 0; i < 2u * (size_t)ow * (size_t)oh; i++)
            map[i] = take_u8(r) & 1 ? take_i32(r) : (int32_t)(take_u8(r) * 16);
        memset(dst, 0xa5, dn);
        int st = sfm_stereo_remap(src, sw, sh, ss, map, ow, oh, 7, dst, ds);
        if (st != SFM_OK) {
            for (size_t i = 0; i < dn; i++)
                if (dst[i] != 0xa5)
                    abort();
        } else {
            for (int y = 0; y < oh; y++)
                for (int x = ow; x < ds; x++)
                    if (dst[(size_t)y * ds + x] != 0xa5)
                        abort();
            for (size_t i = (size_t)ds * oh; i < dn; i++)
                if (dst[i] != 0xa5)
                    abort();
        }
    }
    free(src);
    free(map);
    free(dst);
}

static void op_match(reader *r, int block)
{
    int w = (int)(take_u8(r) % 25) + 16, h = (int)(take_u8(r) % 25) + 16;
    int stride = w + (int)(take_u8(r) % 3) - 1;
    int mind = (int)(int8_t)take_u8(r), nd = (int)(take_u8(r) % 5) * 8;
    size_t n = (size_t)(stride > w ? stride : w) * (size_t)h;
    uint8_t *L = malloc(n), *R = malloc(n);
    float *disp = malloc((size_t)w * h * sizeof *disp);
    if (!L || !R || !disp)
        goto done;
    for (size_t i = 0; i < n; i++) {
        L[i] = (uint8_t)take_u8(r);
        R[i] = (uint8_t)take_u8(r);
    }
    memset(disp, 0x7b, (size_t)w * h * sizeof *disp);
    size_t need;
    void *ws = NULL;
    int st;
    if (block) {
        sfm_stereo_block_options o;
        sfm_stereo_block_default_options(&o);
        o.min_disparity = mind;
        o.num_disparities = nd;
        o.radius = (int)(take_u8(r) % 7);
        o.texture = (int)(take_u8(r) % 16);
        o.lr_max_diff = (int)(take_u8(r) % 4) - 1;
        need = sfm_stereo_block_workspace_size(w, h, &o);
        ws = malloc(need ? need : 1);
        st = ws ? sfm_stereo_block(L, R, w, h, stride, &o, disp, ws, need) : SFM_OK;
    } else {
        sfm_stereo_sgm_options o;
        sfm_stereo_sgm_default_options(&o);
        o.min_disparity = mind;
        o.num_disparities = nd;
        unsigned pth = take_u8(r) % 4;
        o.paths = pth == 0 ? 4 : pth == 1 ? 5 : pth == 2 ? 8 : 3;
        o.p1 = (int)(take_u8(r) % 20);
        o.p2 = (int)(take_u8(r) % 200);
        o.lr_max_diff = (int)(take_u8(r) % 4) - 1;
        need = sfm_stereo_sgm_workspace_size(w, h, &o);
        ws = malloc(need ? need : 1);
        st = ws ? sfm_stereo_sgm(L, R, w, h, stride, &o, disp, ws, need) : SFM_OK;
    }
    if (ws == NULL)
        goto done;
    if (st < 0) {
        float c;
        memset(&c, 0x7b, sizeof c);
        for (int i = 0; i < w * h; i++)
            if (memcmp(&disp[i], &c, sizeof c) != 0)
                abort();
        if (st != SFM_E_ARGUMENT && st != SFM_E_WORKSPACE)
            abort();
    } else {
        int valid = 0;
        for (int i = 0; i < w * h; i++) {
            float d = disp[i];
            if (isnan(d))
                continue;
            valid++;
            if (!(d >= (float)mind - 1.0f && d <= (float)(mind + nd)))
                abort();
        }
        if (valid != st)
            abort();
    }
    free(ws);
done:
    free(L);
    free(R);
    free(disp);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader r = {data, size};
    switch (take_u8(&r) % 4) {
    case 0: op_rectify(&r); break;
    case 1: op_remap(&r); break;
    case 2: op_match(&r, 0); break;
    default: op_match(&r, 1); break;
    }
    return 0;
}
