/*
 * Photometric refinement of corresponding points (the public entry
 * sfm_features_align_points).
 *
 * Lucas and Kanade, "An iterative image registration technique with an
 * application to stereo vision", IJCAI 1981, in the inverse-compositional
 * form of Baker and Matthews, "Lucas-Kanade 20 years on", IJCV 2004: the
 * template is the reference image's square patch around its point, sampled
 * bilinearly, with its gradients (central differences of the samples) and
 * Gauss-Newton matrix computed once; each iteration samples the other
 * image's patch at the current estimate and moves it by the step that the
 * template's linearisation gives. Translation only: over a patch of radius 7
 * a rotation of 2 degrees or a scale change of 2 % moves the patch's rim by a
 * quarter pixel at most, and the error it leaves is symmetric about the
 * centre, so it biases the centre little.
 *
 * Gain and bias: both patches are compared after removing their means, the
 * moving patch scaled by the least-squares gain onto the template (an
 * exposure change between views of JPEG images is common). Acceptance: the
 * template's Gauss-Newton matrix must determine both axes (smaller
 * eigenvalue against the larger and against the patch size: an edge leaves
 * its tangent free), the iteration must settle, stay within max_shift of its
 * start and inside the image, and the aligned patches' zero-mean normalised
 * correlation must reach min_zncc. A point that fails keeps its start.
 *
 * Stack: three float arrays of (2 SFM_FEATURES_ALIGN_MAX_RADIUS + 3)^2
 * entries and one of (2 SFM_FEATURES_ALIGN_MAX_RADIUS + 1)^2 (5.5 KB at
 * radius 8); no workspace, no allocation.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_features.h"

#define SIDE_MAX (2 * SFM_FEATURES_ALIGN_MAX_RADIUS + 3)
/* Converged once the step is below this (pixels). */
#define STEP_DONE 0.01

int sfm_features_default_align_params(sfm_align_params *p)
{
    if (p == NULL)
        return SFM_E_ARGUMENT;
    p->radius = 7;
    p->max_iterations = 20;
    p->max_shift = 3.0;
    p->min_zncc = 0.8;
    p->min_eigen_ratio = 0.05;
    return SFM_OK;
}

static int params_ok(const sfm_align_params *p)
{
    return p->radius >= 2 && p->radius <= SFM_FEATURES_ALIGN_MAX_RADIUS && p->max_iterations >= 1 &&
           p->max_iterations <= 100 && isfinite(p->max_shift) && p->max_shift > 0.0 && isfinite(p->min_zncc) &&
           p->min_zncc >= -1.0 && p->min_zncc <= 1.0 && isfinite(p->min_eigen_ratio) && p->min_eigen_ratio >= 0.0 &&
           p->min_eigen_ratio <= 1.0;
}

static int image_ok(const sfm_image_u8 *im)
{
    return im != NULL && im->data != NULL && im->width >= 1 && im->height >= 1 && im->stride >= im->width;
}

/* 1 when the bilinear footprint of the (2 h + 1)^2 grid centred on (x, y)
 * lies inside the image. In doubles: a point far outside the image (1e300,
 * or past the int range) must not reach an int conversion. */
static int inside(const sfm_image_u8 *im, double x, double y, int h)
{
    const double fx = floor(x), fy = floor(y);
    return fx - h >= 0.0 && fy - h >= 0.0 && fx + h + 1.0 <= (double)(im->width - 1) &&
           fy + h + 1.0 <= (double)(im->height - 1);
}

/* Samples the (2 h + 1)^2 grid centred on (x, y) bilinearly into out (row
 * major). 0 when the grid's bilinear footprint leaves the image. */
static int sample(const sfm_image_u8 *im, double x, double y, int h, float *out)
{
    if (!inside(im, x, y, h))
        return 0;
    const double fx = floor(x), fy = floor(y);
    const int x0 = (int)fx - h, y0 = (int)fy - h, n = 2 * h + 1;
    const double ax = x - fx, ay = y - fy;
    const double w00 = (1.0 - ax) * (1.0 - ay), w01 = ax * (1.0 - ay), w10 = (1.0 - ax) * ay, w11 = ax * ay;
    for (int v = 0; v < n; v++) {
        const uint8_t *r0 = im->data + (size_t)(y0 + v) * (size_t)im->stride + x0;
        const uint8_t *r1 = r0 + im->stride;
        for (int u = 0; u < n; u++)
            out[v * n + u] = (float)(w00 * r0[u] + w01 * r0[u + 1] + w10 * r1[u] + w11 * r1[u + 1]);
    }
    return 1;
}

/* One point: 1 and *ox, *oy refined, or 0. */
static int align_one(const sfm_image_u8 *ref, double rx, double ry, const sfm_image_u8 *img, double x, double y,
                     const sfm_align_params *p, double *ox, double *oy)
{
    const int r = p->radius, n = 2 * r + 1, ne = n + 2;
    float ext[SIDE_MAX * SIDE_MAX], gx[SIDE_MAX * SIDE_MAX], gy[SIDE_MAX * SIDE_MAX];
    if (!sample(ref, rx, ry, r + 1, ext))
        return 0;
    /* template: zero mean; gradients by central differences */
    double mt = 0.0;
    for (int v = 0; v < n; v++)
        for (int u = 0; u < n; u++) {
            const float *c = ext + (v + 1) * ne + (u + 1);
            gx[v * n + u] = 0.5f * (c[1] - c[-1]);
            gy[v * n + u] = 0.5f * (c[ne] - c[-ne]);
            mt += (double)c[0];
        }
    mt /= (double)(n * n);
    /* the zero-mean template packed to n x n at the front of ext (every
     * entry moves to a lower index, in increasing order: no read of an entry
     * already overwritten) */
    for (int v = 0; v < n; v++)
        for (int u = 0; u < n; u++)
            ext[v * n + u] = (float)((double)ext[(v + 1) * ne + (u + 1)] - mt);
    double a = 0.0, b = 0.0, c = 0.0, tt = 0.0;
    for (int k = 0; k < n * n; k++) {
        const double gu = (double)gx[k], gv = (double)gy[k], t = (double)ext[k];
        a += gu * gu;
        b += gu * gv;
        c += gv * gv;
        tt += t * t;
    }
    const double det = a * c - b * b, tr = a + c;
    const double q = 0.25 * tr * tr - det, disc = q > 0.0 ? sqrt(q) : 0.0;
    const double lmin = 0.5 * tr - disc, lmax = 0.5 * tr + disc;
    /* both axes determined, and a gradient of a gray level per pixel at least */
    if (!(lmin > p->min_eigen_ratio * lmax) || !(lmin >= (double)(n * n)) || !(tt > 0.0))
        return 0;
    float patch[(2 * SFM_FEATURES_ALIGN_MAX_RADIUS + 1) * (2 * SFM_FEATURES_ALIGN_MAX_RADIUS + 1)];
    double cx = x, cy = y, zncc = -1.0;
    int settled = 0;
    for (int it = 0; it < p->max_iterations; it++) {
        if (!sample(img, cx, cy, r, patch))
            return 0;
        double mi = 0.0;
        for (int k = 0; k < n * n; k++)
            mi += (double)patch[k];
        mi /= (double)(n * n);
        double ti = 0.0, ii = 0.0;
        for (int k = 0; k < n * n; k++) {
            const double d = (double)patch[k] - mi;
            ti += (double)ext[k] * d;
            ii += d * d;
        }
        if (!(ii > 0.0))
            return 0;
        const double gain = ti / ii;
        zncc = ti / sqrt(ii * tt);
        double ex = 0.0, ey = 0.0;
        for (int k = 0; k < n * n; k++) {
            const double e = gain * ((double)patch[k] - mi) - (double)ext[k];
            ex += (double)gx[k] * e;
            ey += (double)gy[k] * e;
        }
        const double dx = (c * ex - b * ey) / det, dy = (a * ey - b * ex) / det;
        cx -= dx;
        cy -= dy;
        if (!(fabs(cx - x) <= p->max_shift && fabs(cy - y) <= p->max_shift))
            return 0;
        if (dx * dx + dy * dy < STEP_DONE * STEP_DONE) {
            settled = 1;
            break;
        }
    }
    /* the last step is not sampled: it may cross the border (by less than
     * STEP_DONE), and a patch leaving the image is not an answer */
    if (!settled || !(zncc >= p->min_zncc) || !inside(img, cx, cy, r))
        return 0;
    *ox = cx;
    *oy = cy;
    return 1;
}

int sfm_features_align_points(const sfm_image_u8 *ref, const double *x_ref, const sfm_image_u8 *img,
                              const double *x, int n, const sfm_align_params *p, double *out, uint8_t *refined)
{
    if (!image_ok(ref) || !image_ok(img) || p == NULL || n < 0 || (n > 0 && (x_ref == NULL || x == NULL ||
                                                                            out == NULL || refined == NULL)))
        return SFM_E_ARGUMENT;
    if (!params_ok(p))
        return SFM_E_ARGUMENT;
    for (int k = 0; k < 2 * n; k++)
        if (!isfinite(x_ref[k]) || !isfinite(x[k]))
            return SFM_E_NONFINITE;
    int count = 0;
    for (int k = 0; k < n; k++) {
        double qx = x[2 * k], qy = x[2 * k + 1];
        const int ok = align_one(ref, x_ref[2 * k], x_ref[2 * k + 1], img, qx, qy, p, &qx, &qy);
        out[2 * k] = qx;
        out[2 * k + 1] = qy;
        refined[k] = (uint8_t)ok;
        count += ok;
    }
    return count;
}
