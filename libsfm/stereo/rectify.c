/*
 * Rectification of a calibrated pair: Fusiello, Trucco, Verri, "A compact
 * algorithm for rectification of stereo pairs", Machine Vision and
 * Applications 12 (2000). Both rectified cameras take one rotation: x along
 * the baseline c2 - c1, y normal to it and to the mean optical axis (the
 * paper uses camera 1's axis; the mean turns the two views equally), z
 * completing the frame. The new intrinsics are chosen from where the image
 * borders land, as OpenCV's stereoRectify chooses them from alpha.
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_stereo.h"
#include "solvers/small_math.h"
#include "stereo/stereo_internal.h"

#define BORDER_SAMPLES 24 /* per image side */

/* Where the border of one image lands in rectified normalized coordinates:
 * the outer box of all border samples, and the inner rectangle bounded by
 * the innermost sample of each side (sides classified by where they land,
 * since a rectified view may be turned). Returns 0 when too few samples
 * rectify. */
typedef struct box {
    double ox0, ox1, oy0, oy1; /* outer */
    double ix0, ix1, iy0, iy1; /* inner */
} box;

static int border_box(const sfm_camera *cam, int w, int h, const double *Rr, box *b)
{
    double side_x[4][BORDER_SAMPLES], side_y[4][BORDER_SAMPLES];
    int cnt[4] = {0, 0, 0, 0};
    double mx[4] = {0, 0, 0, 0}, my[4] = {0, 0, 0, 0};
    int total = 0;
    b->ox0 = b->oy0 = HUGE_VAL;
    b->ox1 = b->oy1 = -HUGE_VAL;
    for (int s = 0; s < 4; s++) {
        for (int k = 0; k < BORDER_SAMPLES; k++) {
            double a = (double)k / (double)(BORDER_SAMPLES - 1);
            double px[2];
            if (s == 0) { px[0] = 0.0; px[1] = a * (h - 1); }            /* left */
            else if (s == 1) { px[0] = w - 1.0; px[1] = a * (h - 1); }   /* right */
            else if (s == 2) { px[0] = a * (w - 1); px[1] = 0.0; }       /* top */
            else { px[0] = a * (w - 1); px[1] = h - 1.0; }               /* bottom */
            double ray[3], r[3];
            if (sfm_camera_unproject(cam, px, ray) != SFM_OK)
                continue;
            sfmi_matvec3(Rr, ray, r);
            if (!(r[2] > 1e-3 * sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])))
                continue;
            double x = r[0] / r[2], y = r[1] / r[2];
            side_x[s][cnt[s]] = x;
            side_y[s][cnt[s]] = y;
            cnt[s]++;
            mx[s] += x;
            my[s] += y;
            total++;
            if (x < b->ox0) b->ox0 = x;
            if (x > b->ox1) b->ox1 = x;
            if (y < b->oy0) b->oy0 = y;
            if (y > b->oy1) b->oy1 = y;
        }
    }
    for (int s = 0; s < 4; s++)
        if (cnt[s] < 2)
            return 0;
    (void)total;
    for (int s = 0; s < 4; s++) {
        mx[s] /= cnt[s];
        my[s] /= cnt[s];
    }
    /* Which landed side is left, right, top, bottom: the extreme means. */
    int sl = 0, sr = 0, st = 0, sb = 0;
    for (int s = 1; s < 4; s++) {
        if (mx[s] < mx[sl]) sl = s;
        if (mx[s] > mx[sr]) sr = s;
        if (my[s] < my[st]) st = s;
        if (my[s] > my[sb]) sb = s;
    }
    b->ix0 = -HUGE_VAL;
    b->ix1 = HUGE_VAL;
    b->iy0 = -HUGE_VAL;
    b->iy1 = HUGE_VAL;
    for (int k = 0; k < cnt[sl]; k++) if (side_x[sl][k] > b->ix0) b->ix0 = side_x[sl][k];
    for (int k = 0; k < cnt[sr]; k++) if (side_x[sr][k] < b->ix1) b->ix1 = side_x[sr][k];
    for (int k = 0; k < cnt[st]; k++) if (side_y[st][k] > b->iy0) b->iy0 = side_y[st][k];
    for (int k = 0; k < cnt[sb]; k++) if (side_y[sb][k] < b->iy1) b->iy1 = side_y[sb][k];
    return b->ox1 > b->ox0 && b->oy1 > b->oy0;
}

static int clampi(double v, int lo, int hi)
{
    if (!(v > lo)) return lo;
    if (v > hi) return hi;
    return (int)v;
}

static void roi_of(const box *b, double f, double cx, double cy, int W, int H, int *roi)
{
    int x0 = clampi(ceil(f * b->ix0 + cx), 0, W);
    int x1 = clampi(floor(f * b->ix1 + cx), -1, W - 1);
    int y0 = clampi(ceil(f * b->iy0 + cy), 0, H);
    int y1 = clampi(floor(f * b->iy1 + cy), -1, H - 1);
    roi[0] = x0;
    roi[1] = y0;
    roi[2] = x1 >= x0 ? x1 - x0 + 1 : 0;
    roi[3] = y1 >= y0 ? y1 - y0 + 1 : 0;
}

int sfm_stereo_rectify(const sfm_camera *cam1, const sfm_camera *cam2, int width, int height,
                       const double R[9], const double t[3], double alpha, int out_width,
                       int out_height, sfm_stereo_rectification *out)
{
    if (!cam1 || !cam2 || !R || !t || !out)
        return SFM_E_ARGUMENT;
    int st = sfm_camera_validate(cam1);
    if (st < 0)
        return st;
    st = sfm_camera_validate(cam2);
    if (st < 0)
        return st;
    if (!sfmi_all_finite9(R) || !sfmi_all_finite3(t) || !isfinite(alpha))
        return SFM_E_NONFINITE;
    if (width < 8 || height < 8 || width > 32767 || height > 32767)
        return SFM_E_ARGUMENT;
    if (out_width <= 0 || out_height <= 0) {
        out_width = width;
        out_height = height;
    }
    if (out_width < 8 || out_height < 8 || out_width > 32767 || out_height > 32767)
        return SFM_E_ARGUMENT;
    if (!(alpha == -1.0 || (alpha >= 0.0 && alpha <= 1.0)))
        return SFM_E_ARGUMENT;
    if (!sfmi_la_is_rotation(R, 1e-4))
        return SFM_E_ARGUMENT;
    /* Rotations read from files carry a few digits only: use the nearest
     * rotation, so that the rectified frames are exactly orthonormal. */
    double Rn[9];
    if (sfm_rot_nearest(R, Rn) != SFM_OK)
        return SFM_E_ARGUMENT;
    R = Rn;

    /* c2 = -R^T t in camera 1's frame; camera 2's optical axis there is the
     * third row of R. */
    double c2[3] = {-(R[0] * t[0] + R[3] * t[1] + R[6] * t[2]),
                    -(R[1] * t[0] + R[4] * t[1] + R[7] * t[2]),
                    -(R[2] * t[0] + R[5] * t[1] + R[8] * t[2])};
    double B = sqrt(sfmi_dot3(c2, c2));
    if (!(B > 0.0) || !isfinite(B))
        return SFM_E_SINGULAR;
    double v1[3] = {c2[0] / B, c2[1] / B, c2[2] / B};
    double zm[3] = {R[6], R[7], 1.0 + R[8]};
    double v2[3], v3[3];
    sfmi_cross3(zm, v1, v2);
    double n2 = sqrt(sfmi_dot3(v2, v2)), nz = sqrt(sfmi_dot3(zm, zm));
    /* sin(1 degree): the baseline within a degree of the viewing direction
     * puts the epipoles inside the images. */
    if (!(nz > 1e-6) || !(n2 > 0.0174524 * nz))
        return SFM_E_SINGULAR;
    for (int k = 0; k < 3; k++)
        v2[k] /= n2;
    sfmi_cross3(v1, v2, v3);
    double Rr[9] = {v1[0], v1[1], v1[2], v2[0], v2[1], v2[2], v3[0], v3[1], v3[2]};
    double Rt[9] = {R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8]};
    double R2[9];
    sfmi_matmul3(Rr, Rt, R2);

    box b1, b2;
    if (!border_box(cam1, width, height, Rr, &b1) || !border_box(cam2, width, height, R2, &b2))
        return SFM_E_SINGULAR;
    double W = out_width - 1.0, H = out_height - 1.0;
    /* Vertical extents are shared: rows must stay aligned. */
    double oy0 = fmin(b1.oy0, b2.oy0), oy1 = fmax(b1.oy1, b2.oy1);
    double iy0 = fmax(b1.iy0, b2.iy0), iy1 = fmin(b1.iy1, b2.iy1);
    int inner_ok = b1.ix1 > b1.ix0 && b2.ix1 > b2.ix0 && iy1 > iy0;
    double f_out = fmin(fmin(W / (b1.ox1 - b1.ox0), W / (b2.ox1 - b2.ox0)), H / (oy1 - oy0));
    double f_in = inner_ok ? fmax(fmax(W / (b1.ix1 - b1.ix0), W / (b2.ix1 - b2.ix0)),
                                  H / (iy1 - iy0))
                           : f_out;
    double f, mix;
    if (alpha == -1.0) {
        f = 0.5 * (cam1->fy + cam2->fy);
        f = fabs(f);
        mix = 0.0;
    } else {
        f = f_in * (1.0 - alpha) + f_out * alpha;
        mix = alpha;
    }
    if (!inner_ok)
        mix = 1.0;
    if (!(f > 0.0) || !isfinite(f))
        return SFM_E_SINGULAR;
    double mid1 = (1.0 - mix) * 0.5 * (b1.ix0 + b1.ix1) + mix * 0.5 * (b1.ox0 + b1.ox1);
    double mid2 = (1.0 - mix) * 0.5 * (b2.ix0 + b2.ix1) + mix * 0.5 * (b2.ox0 + b2.ox1);
    double midy = (1.0 - mix) * 0.5 * (iy0 + iy1) + mix * 0.5 * (oy0 + oy1);
    double cx1 = 0.5 * W - f * mid1, cx2 = 0.5 * W - f * mid2, cy = 0.5 * H - f * midy;

    sfm_stereo_rectification r;
    memset(&r, 0, sizeof r);
    memcpy(r.R1, Rr, sizeof Rr);
    memcpy(r.R2, R2, sizeof R2);
    double K1[9] = {f, 0, cx1, 0, f, cy, 0, 0, 1};
    double K2[9] = {f, 0, cx2, 0, f, cy, 0, 0, 1};
    memcpy(r.K1, K1, sizeof K1);
    memcpy(r.K2, K2, sizeof K2);
    r.baseline = B;
    double Q[16] = {1, 0, 0, -cx1, 0, 1, 0, -cy, 0, 0, 0, f, 0, 0, 1.0 / B, -(cx1 - cx2) / B};
    memcpy(r.Q, Q, sizeof Q);
    r.width = out_width;
    r.height = out_height;
    roi_of(&b1, f, cx1, cy, out_width, out_height, r.roi1);
    roi_of(&b2, f, cx2, cy, out_width, out_height, r.roi2);
    if (r.roi1[2] == 0 && r.roi2[2] == 0 && alpha != 1.0) {
        /* Nothing of either view is inside its output: unusable. */
        double probe = fmin(f * (b1.ox1 - b1.ox0), f * (b2.ox1 - b2.ox0));
        if (!(probe >= 1.0))
            return SFM_E_SINGULAR;
    }
    *out = r;
    return SFM_OK;
}

/* Fixed-point source coordinate, or -1 when the bilinear footprint leaves
 * [0, size - 1]. */
static int32_t fixed_coord(double v, int size)
{
    if (!(v >= 0.0) || !(v <= size - 1.0))
        return -1;
    double s = floor(v * SFM_STEREO_MAP_ONE + 0.5);
    if (s > (double)(size - 1) * SFM_STEREO_MAP_ONE)
        s = (double)(size - 1) * SFM_STEREO_MAP_ONE;
    return (int32_t)s;
}

/* Map entry m (2 int32) of the source point (x, y) in a width x height
 * image: both fixed-point coordinates, or -1, -1 when either leaves it. */
static void map_entry(int32_t *m, double x, double y, int width, int height)
{
    int32_t fx = fixed_coord(x, width), fy = fixed_coord(y, height);
    if (fx < 0 || fy < 0)
        fx = fy = -1;
    m[0] = fx;
    m[1] = fy;
}

int sfm_stereo_rectify_map(const sfm_camera *cam, int src_width, int src_height,
                           const sfm_stereo_rectification *rect, int view, int32_t *map,
                           size_t map_len)
{
    if (!cam || !rect || !map || (view != 1 && view != 2))
        return SFM_E_ARGUMENT;
    int st = sfm_camera_validate(cam);
    if (st < 0)
        return st;
    if (src_width < 2 || src_height < 2 || src_width > 32767 || src_height > 32767 ||
        rect->width < 1 || rect->height < 1 || rect->width > 32767 || rect->height > 32767)
        return SFM_E_ARGUMENT;
    if (map_len < 2u * (size_t)rect->width * (size_t)rect->height)
        return SFM_E_ARGUMENT;
    const double *Rr = view == 1 ? rect->R1 : rect->R2;
    const double *K = view == 1 ? rect->K1 : rect->K2;
    if (!sfmi_all_finite9(Rr) || !sfmi_all_finite9(K))
        return SFM_E_NONFINITE;
    if (!(K[0] != 0.0) || !(K[4] != 0.0))
        return SFM_E_ARGUMENT;
    double ifx = 1.0 / K[0], ify = 1.0 / K[4];
    for (int v = 0; v < rect->height; v++) {
        double yn = (v - K[5]) * ify;
        for (int u = 0; u < rect->width; u++) {
            double xn = (u - K[2]) * ifx;
            /* x_cam = R^T x_rect */
            double X[3] = {Rr[0] * xn + Rr[3] * yn + Rr[6], Rr[1] * xn + Rr[4] * yn + Rr[7],
                           Rr[2] * xn + Rr[5] * yn + Rr[8]};
            double px[2];
            int32_t *m = map + 2 * ((size_t)v * rect->width + u);
            if (sfm_camera_project(cam, X, px, NULL) != SFM_OK) {
                m[0] = m[1] = -1;
                continue;
            }
            map_entry(m, px[0], px[1], src_width, src_height);
        }
    }
    return SFM_OK;
}

int sfm_stereo_homography_map(const sfm_mat3 *H_in, int src_width, int src_height, int out_width,
                              int out_height, int32_t *map, size_t map_len)
{
    const double *H = H_in ? H_in->m : NULL;
    if (!H || !map || src_width < 2 || src_height < 2 || out_width < 1 || out_height < 1 ||
        src_width > 32767 || src_height > 32767 || out_width > 32767 || out_height > 32767)
        return SFM_E_ARGUMENT;
    if (map_len < 2u * (size_t)out_width * (size_t)out_height)
        return SFM_E_ARGUMENT;
    if (!sfmi_all_finite9(H))
        return SFM_E_NONFINITE;
    double Hi[9];
    if (sfmi_stereo_inv3(H, Hi) != SFM_OK)
        return SFM_E_SINGULAR;
    for (int v = 0; v < out_height; v++) {
        for (int u = 0; u < out_width; u++) {
            double p[3] = {u, v, 1.0}, q[3];
            sfmi_matvec3(Hi, p, q);
            int32_t *m = map + 2 * ((size_t)v * out_width + u);
            if (!(fabs(q[2]) > 1e-300)) {
                m[0] = m[1] = -1;
                continue;
            }
            map_entry(m, q[0] / q[2], q[1] / q[2], src_width, src_height);
        }
    }
    return SFM_OK;
}

int sfm_stereo_remap(const uint8_t *src, int src_width, int src_height, int src_stride,
                     const int32_t *map, int out_width, int out_height, uint8_t fill,
                     uint8_t *dst, int dst_stride)
{
    if (!src || !map || !dst || src_width < 1 || src_height < 1 || out_width < 1 ||
        out_height < 1 || src_stride < src_width || dst_stride < out_width)
        return SFM_E_ARGUMENT;
    const int32_t xmax = (src_width - 1) * SFM_STEREO_MAP_ONE;
    const int32_t ymax = (src_height - 1) * SFM_STEREO_MAP_ONE;
    for (int v = 0; v < out_height; v++) {
        const int32_t *m = map + 2 * (size_t)v * out_width;
        uint8_t *d = dst + (size_t)v * dst_stride;
        for (int u = 0; u < out_width; u++) {
            int32_t X = m[2 * u], Y = m[2 * u + 1];
            if (X < 0 || Y < 0 || X > xmax || Y > ymax) {
                d[u] = fill;
                continue;
            }
            int x0 = X >> 8, y0 = Y >> 8;
            uint32_t ax = (uint32_t)(X & 255), ay = (uint32_t)(Y & 255);
            int x1 = x0 + (ax != 0), y1 = y0 + (ay != 0);
            const uint8_t *r0 = src + (size_t)y0 * src_stride, *r1 = src + (size_t)y1 * src_stride;
            uint32_t top = r0[x0] * (256u - ax) + r0[x1] * ax;
            uint32_t bot = r1[x0] * (256u - ax) + r1[x1] * ax;
            d[u] = (uint8_t)((top * (256u - ay) + bot * ay + 32768u) >> 16);
        }
    }
    return SFM_OK;
}

static int rectify_point(const sfm_camera *cam, const double *Rr, const double *K,
                         const double *px, double *out)
{
    double b[3], r[3];
    if (sfm_camera_unproject(cam, px, b) != SFM_OK)
        return 0;
    sfmi_matvec3(Rr, b, r);
    if (!(r[2] > 0.0))
        return 0;
    out[0] = K[0] * r[0] / r[2] + K[2];
    out[1] = K[4] * r[1] / r[2] + K[5];
    return 1;
}

static int apply_h(const double *H, const double *px, double *out)
{
    double p[3] = {px[0], px[1], 1.0}, q[3];
    sfmi_matvec3(H, p, q);
    if (!(fabs(q[2]) > 1e-300))
        return 0;
    out[0] = q[0] / q[2];
    out[1] = q[1] / q[2];
    return isfinite(out[0]) && isfinite(out[1]);
}

/* The row difference |y1 - y2| of match i after rectification (rect) or the
 * homographies H1, H2; 0 when a point does not map. */
static int match_dy(const sfm_camera *cam1, const sfm_camera *cam2,
                    const sfm_stereo_rectification *rect, const double *H1, const double *H2,
                    const double *x1, const double *x2, int i, double *dy)
{
    double a[2], b[2];
    int ok = rect ? rectify_point(cam1, rect->R1, rect->K1, x1 + 2 * i, a) &&
                        rectify_point(cam2, rect->R2, rect->K2, x2 + 2 * i, b)
                  : apply_h(H1, x1 + 2 * i, a) && apply_h(H2, x2 + 2 * i, b);
    if (ok)
        *dy = fabs(a[1] - b[1]);
    return ok;
}

int sfm_stereo_rectification_error(const sfm_camera *cam1, const sfm_camera *cam2,
                                   const sfm_stereo_rectification *rect, const sfm_mat3 *H1_in,
                                   const sfm_mat3 *H2_in, const double *x1, const double *x2, int n,
                                   double *median_dy, double *max_dy)
{
    const double *H1 = H1_in ? H1_in->m : NULL;
    const double *H2 = H2_in ? H2_in->m : NULL;
    if (!x1 || !x2 || n < 0 || !median_dy || !max_dy)
        return SFM_E_ARGUMENT;
    if (rect ? (!cam1 || !cam2) : (!H1 || !H2))
        return SFM_E_ARGUMENT;
    if (rect) {
        int st = sfm_camera_validate(cam1);
        if (st == SFM_OK)
            st = sfm_camera_validate(cam2);
        if (st < 0)
            return st;
        /* A NaN rotation or intrinsic would give NaN row differences, which
         * the max and the median's bisection would count as 0. */
        if (!sfmi_all_finite9(rect->R1) || !sfmi_all_finite9(rect->R2) ||
            !sfmi_all_finite9(rect->K1) || !sfmi_all_finite9(rect->K2))
            return SFM_E_NONFINITE;
    }
    if (!rect && (!sfmi_all_finite9(H1) || !sfmi_all_finite9(H2)))
        return SFM_E_NONFINITE;
    for (int i = 0; i < 2 * n; i++)
        if (!isfinite(x1[i]) || !isfinite(x2[i]))
            return SFM_E_NONFINITE;
    /* No buffer to sort: the median is found by bisection on its value,
     * counting the matches below each guess. */
    int used = 0;
    double mx = 0.0;
    for (int i = 0; i < n; i++) {
        double dy;
        if (!match_dy(cam1, cam2, rect, H1, H2, x1, x2, i, &dy))
            continue;
        if (dy > mx)
            mx = dy;
        used++;
    }
    if (used == 0) {
        *median_dy = (double)NAN;
        *max_dy = (double)NAN;
        return 0;
    }
    double lo = 0.0, hi = mx;
    int k = (used + 1) / 2; /* the k-th smallest */
    for (int it = 0; it < 60 && hi > lo; it++) {
        double midv = 0.5 * (lo + hi);
        int below = 0;
        for (int i = 0; i < n; i++) {
            double dy;
            if (match_dy(cam1, cam2, rect, H1, H2, x1, x2, i, &dy) && dy <= midv)
                below++;
        }
        if (below >= k)
            hi = midv;
        else
            lo = midv;
    }
    *median_dy = hi;
    *max_dy = mx;
    return used;
}
