/* Shared input handling of the fundamental and homography estimators. */
#include "robust/pixel_pairs.h"

#include <string.h>

#include "robust/estimator.h"
#include "robust/support_check.h"
#include "solvers/normalize.h"

static void layout(sfmi_arena *a, int n, size_t es, pixel_pairs *pp)
{
    pp->p1 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    pp->p2 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    pp->g1 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    pp->g2 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    pp->idx = SFM_ARENA_ARRAY(a, int, n);
    pp->eng = sfmi_arena_alloc(a, es);
    pp->eng_size = es;
}

size_t sfmi_pixel_pairs_workspace_size(int n, int sample, int max_models, int model_size)
{
    if (n < sample || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    size_t es = sfmi_robust_engine_size(n, sample, max_models, model_size);
    if (es == 0)
        return 0;
    sfmi_arena a;
    pixel_pairs pp;
    sfmi_arena_measure(&a);
    layout(&a, n, es, &pp);
    return sfmi_arena_required(&a);
}

static int ideal(const sfm_camera *cam, const double *px, int n, double *out)
{
    for (int i = 0; i < n; i++) {
        double b[3];
        int st = sfm_camera_unproject(cam, px + 2 * i, b);
        if (st < 0)
            return st;
        if (b[2] > 1e-9) {
            out[2 * i] = cam->fx * b[0] / b[2] + cam->cx;
            out[2 * i + 1] = cam->fy * b[1] / b[2] + cam->cy;
        } else {
            /* behind the image plane of a wide camera: no pinhole pixel; a
             * far point that no model explains */
            out[2 * i] = 1e9;
            out[2 * i + 1] = 1e9;
        }
    }
    return SFM_OK;
}

int sfmi_pixel_pairs_setup(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                          const sfm_camera *cam2, const sfm_ransac_options *opt, int sample,
                          int max_models, int model_size, void *ws, size_t ws_size,
                          pixel_pairs *pp, sfm_ransac_options *eopt)
{
    if (px1 == NULL || px2 == NULL || ws == NULL || (cam1 == NULL) != (cam2 == NULL))
        return SFM_E_ARGUMENT;
    int st = sfmi_robust_pair_inputs(px1, px2, n, sample, cam1, cam2, opt, eopt);
    if (st < 0)
        return st;
    size_t need = sfmi_pixel_pairs_workspace_size(n, sample, max_models, model_size);
    if (need == 0)
        return SFM_E_ARGUMENT;
    if (ws_size < need)
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, n, sfmi_robust_engine_size(n, sample, max_models, model_size), pp);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    if (cam1 == NULL) {
        memcpy(pp->p1, px1, 2 * (size_t)n * sizeof(double));
        memcpy(pp->p2, px2, 2 * (size_t)n * sizeof(double));
        return SFM_OK;
    }
    st = ideal(cam1, px1, n, pp->p1);
    if (st < 0)
        return st;
    return ideal(cam2, px2, n, pp->p2);
}

void sfmi_pixel_pairs_refit(const double *p1, const double *p2, const int *inl, int n,
                            double tau, sfmi_pair_fit_fn fit, sfmi_pair_cost_fn cost,
                            double *g1, double *g2, double M[9])
{
    sfmi_robust_gather(p1, 2, inl, n, g1);
    sfmi_robust_gather(p2, 2, inl, n, g2);
    sfm_mat3 L;
    if (fit(g1, g2, n, &L) == 1 && sfmi_normalize9(L.m) == 0 &&
        cost(g1, g2, n, tau, L.m) < cost(g1, g2, n, tau, M))
        memcpy(M, L.m, 9 * sizeof(double));
}

int sfmi_pixel_pairs_support(const pixel_pairs *pp, int n, int k, int m, double p, int homography,
                            double tau)
{
    if (!sfmi_above_chance(n, k, m, p))
        return SFM_E_NO_MODEL;
    sfmi_robust_gather(pp->p1, 2, pp->idx, m, pp->g1);
    sfmi_robust_gather(pp->p2, 2, pp->idx, m, pp->g2);
    const double *img[2] = {pp->p1, pp->p2}, *sup[2] = {pp->g1, pp->g2};
    /* a plane seen edge-on in one image still determines the (singular)
     * homography onto that line, so H needs a line in both images; F,
     * whose points on one image line lie on one plane through that camera
     * centre, is undetermined by a line in either */
    int lines = 0;
    for (int v = 0; v < 2; v++) {
        double diag, lo, hi;
        sfmi_bbox_area(img[v], 2, n, &diag);
        sfmi_spread(sup[v], 2, NULL, m, &lo, &hi);
        lines += sfmi_spread_collinear(lo, hi, tau);
        if (hi < SFMI_CLUSTER_RATIO * diag)
            return SFM_E_DEGENERATE;
    }
    if (lines >= (homography ? 2 : 1))
        return SFM_E_DEGENERATE;
    int st = sfmi_pairs_design_degenerate(pp->g1, pp->g2, m, homography, tau);
    if (st < 0)
        return st;
    return st ? SFM_E_DEGENERATE : SFM_OK;
}
