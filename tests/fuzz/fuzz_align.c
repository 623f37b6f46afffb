/* Fuzz target: sfm_features_align_points. The input chooses the two image
 * views (1 x 1 to 48 x 40, stride padding, pixels from the input or a
 * smooth pattern), the parameters (in or out of range) and up to 8 point
 * pairs as raw doubles (NaN, infinities and 1e300 included). Any input
 * gives a status the header lists; on failure nothing is written; on
 * success every point is written, refined[k] is 0 or 1, a point not
 * refined keeps its start and a refined one lies within max_shift of it,
 * inside the image. The images are exact-size heap blocks (no padding
 * after the last row), so a read past the image is an ASan report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_features.h"

#include "fuzz_reader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A view of w x h with `pad` bytes of padding per row but the last; pixels
 * from the input when `raw`, else blobs of period 7 and 11 pixels. */
static uint8_t *make_image(reader *r, sfm_image_u8 *im)
{
    const int w = 1 + (int)(take_u8(r) % 48), h = 1 + (int)(take_u8(r) % 40);
    const int pad = (int)(take_u8(r) % 5), raw = take_u8(r) & 1;
    const size_t bytes = (size_t)(w + pad) * (size_t)(h - 1) + (size_t)w;
    uint8_t *buf = malloc(bytes);
    if (buf == NULL)
        return NULL;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w + (y < h - 1 ? pad : 0); x++) {
            const double v = 128.0 + 60.0 * sin(0.9 * x) * cos(0.57 * y) + 30.0 * sin(0.3 * (x + 2 * y));
            buf[(size_t)y * (size_t)(w + pad) + (size_t)x] = raw ? (uint8_t)take_u8(r) : (uint8_t)v;
        }
    im->data = buf;
    im->width = w;
    im->height = h;
    im->stride = w + pad;
    return buf;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader r = {data, size};
    sfm_align_params p;
    sfm_features_default_align_params(&p);
    const unsigned sel = take_u8(&r);
    if (sel & 1)
        p.radius = (int)take_u8(&r) - 2; /* -2 .. 253: mostly out of range */
    if (sel & 2)
        p.max_iterations = (int)take_u8(&r) - 5;
    if (sel & 4)
        p.max_shift = take_f64(&r);
    if (sel & 8)
        p.min_zncc = take_f64(&r);
    if (sel & 16)
        p.min_eigen_ratio = take_f64(&r);
    sfm_image_u8 a, b;
    uint8_t *ba = make_image(&r, &a);
    uint8_t *bb = make_image(&r, &b);
    if (ba == NULL || bb == NULL) {
        free(ba);
        free(bb);
        return 0;
    }
    const int n = (int)(take_u8(&r) % 9);
    double xr[16], x[16], out[16], before[16];
    uint8_t ok[8], okb[8];
    for (int k = 0; k < 2 * n; k++) {
        /* either a raw double or a point near the pattern's middle */
        const unsigned mode = take_u8(&r);
        xr[k] = mode & 1 ? take_f64(&r) : (double)(take_u8(&r) % 50) + 0.01 * take_u8(&r);
        x[k] = mode & 2 ? take_f64(&r) : xr[k] + 0.02 * ((int)take_u8(&r) - 128);
    }
    memset(out, 0xA5, sizeof out);
    memset(ok, 0x5A, sizeof ok);
    memcpy(before, out, sizeof out);
    memcpy(okb, ok, sizeof ok);
    const int st = sfm_features_align_points(&a, n ? xr : NULL, &b, n ? x : NULL, n, &p, n ? out : NULL,
                                             n ? ok : NULL);
    if (st < 0) {
        if (st != SFM_E_ARGUMENT && st != SFM_E_NONFINITE)
            abort();
        if (memcmp(out, before, sizeof out) != 0 || memcmp(ok, okb, sizeof ok) != 0)
            abort();
    } else {
        int cnt = 0;
        for (int k = 0; k < n; k++) {
            if (ok[k] > 1)
                abort();
            if (ok[k]) {
                cnt++;
                if (!(fabs(out[2 * k] - x[2 * k]) <= p.max_shift && fabs(out[2 * k + 1] - x[2 * k + 1]) <= p.max_shift))
                    abort();
                if (!(out[2 * k] >= p.radius && out[2 * k] < b.width - 1 - p.radius && out[2 * k + 1] >= p.radius &&
                      out[2 * k + 1] < b.height - 1 - p.radius))
                    abort();
            } else if (memcmp(&out[2 * k], &x[2 * k], 2 * sizeof(double)) != 0) {
                abort();
            }
        }
        if (cnt != st || memcmp(&out[2 * n], &before[2 * n], sizeof(double) * (size_t)(16 - 2 * n)) != 0)
            abort();
    }
    free(ba);
    free(bb);
    return 0;
}
