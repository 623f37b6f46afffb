/*
 * Pose covariances of the final refits (support_pose.h): the refiners' own
 * least-squares problems (sampson_lm.h, reproj_lm.h) handed to the core LM
 * driver with no step allowed, so the covariance comes from the same
 * analytic Jacobians the refits minimise, through the one driver.
 */
#include "robust/support_pose.h"

#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "robust/epipolar.h"
#include "robust/reproj_lm.h"
#include "robust/sampson_lm.h"
#include "sfm/sfm_common.h"

/* cov6 = G C G^T, C nt x nt, G 6 x nt. */
static void map_cov(const double *C, int nt, const double *G, double *cov6)
{
    double GC[6 * 6];
    for (int r = 0; r < 6; r++)
        for (int c = 0; c < nt; c++) {
            double s = 0.0;
            for (int k = 0; k < nt; k++)
                s += G[r * nt + k] * C[k * nt + c];
            GC[r * nt + c] = s;
        }
    for (int r = 0; r < 6; r++)
        for (int c = 0; c < 6; c++) {
            double s = 0.0;
            for (int k = 0; k < nt; k++)
                s += GC[r * nt + k] * G[c * nt + k];
            cov6[6 * r + c] = s;
        }
}

/* The driver's covariance of prob at its blocks' values: SFM_OK with C
 * filled and *ssr the sum of squared residuals, or a negative status. */
static int lm_cov(const sfmi_lm_problem *prob, double *C, double *ssr)
{
    sfmi_lm_options o;
    sfmi_lm_default_options(&o);
    o.max_iterations = 0;
    o.gradient_tolerance = 0.0;
    o.want_covariance = 1;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(12, 6, 2)];
    sfmi_lm_summary sum;
    *ssr = 0.0;
    int st = sfmi_lm_dense_solve(prob, &o, ws, sizeof ws, &sum, C);
    if (st != SFM_OK)
        return st;
    *ssr = 2.0 * sum.final_cost; /* the driver's cost is half the sum */
    return sum.covariance_status == SFM_OK ? SFM_OK : SFM_E_SINGULAR;
}

static void undetermined(double *cov6, int r0)
{
    if (r0 == 0)
        memset(cov6, 0, 36 * sizeof(double));
    for (int r = r0; r < 6; r++)
        cov6[7 * r] = 1e30;
}

int sfmi_relpose_covariance(const double *b1, const double *b2, const int *idx, int m,
                            const double *R, const double *t, const double *axis, double *cov6,
                            double *ssr)
{
    double Rc[9], tc[3], C[25], G[30], B[6];
    memcpy(Rc, R, sizeof Rc);
    memcpy(tc, t, sizeof tc);
    sfmi_sampson_problem sp;
    sfmi_sampson_lm_problem(b1, b2, idx, m, axis, 0.0, Rc, tc, &sp);
    const int nr = axis ? 1 : 3;
    /* G: w is the free rotation (or the angle times the axis); t moves along
     * the sphere block's tangent basis */
    sfmi_lm_sphere_basis(tc, 3, B);
    for (int pass = 0; pass < 2; pass++) {
        const int nt = pass == 0 ? nr + 2 : nr;
        memset(G, 0, sizeof G);
        for (int r = 0; r < 3; r++) {
            if (axis)
                G[r * nt] = axis[r];
            else
                G[r * nt + r] = 1.0;
            if (pass == 0) {
                G[(3 + r) * nt + nr] = B[2 * r];
                G[(3 + r) * nt + nr + 1] = B[2 * r + 1];
            }
        }
        if (lm_cov(&sp.prob, C, ssr) == SFM_OK) {
            map_cov(C, nt, G, cov6);
            if (pass == 1)
                undetermined(cov6, 3);
            return pass;
        }
        /* t undetermined (no parallax): R alone, t held */
        sp.blocks[1].manifold = SFMI_LM_CONSTANT;
    }
    undetermined(cov6, 0);
    return -1;
}

int sfmi_abspose_covariance(const double *b, const double *X, const int *idx, int m,
                            const double *R, const double *t, double *cov6, double *ssr,
                            double *mean_depth)
{
    double Rc[9], tc[3];
    memcpy(Rc, R, sizeof Rc);
    memcpy(tc, t, sizeof tc);
    double dsum = 0.0;
    int nd = 0;
    for (int j = 0; j < m; j++) {
        const double *x = X + 3 * idx[j];
        double Xc[3];
        sfmi_matvec3(R, x, Xc);
        double d = sfmi_dot3(b + 3 * idx[j], Xc) + sfmi_dot3(b + 3 * idx[j], t);
        if (d > 0.0) {
            dsum += d;
            nd++;
        }
    }
    *mean_depth = nd > 0 ? dsum / nd : 0.0;
    sfmi_reproj_problem rp;
    sfmi_reproj_lm_problem(b, X, idx, m, 0.0, Rc, tc, &rp);
    if (lm_cov(&rp.prob, cov6, ssr) != SFM_OK) {
        undetermined(cov6, 0);
        return -1;
    }
    return 0;
}
