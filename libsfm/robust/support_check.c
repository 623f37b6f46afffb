/*
 * Support tests on an estimator's final inlier set (support_check.h).
 *
 * Three questions, asked of the support of the model an estimator is about
 * to return, not of its samples:
 *  - is the support more than random matches would give (chance)?
 *  - is it spread in each image (not on one line, not one small cluster)?
 *  - does it determine the model: one null direction of the normalised
 *    design matrix (linear models), or a bounded covariance of the pose
 *    from the refit's normal equations (pose models)?
 */
#include "robust/support_check.h"

#include <math.h>
#include <string.h>

#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"
#include "solvers/normalize.h"

double sfmi_chance_count(int n, int k, double p)
{
    if (p < 0.0)
        p = 0.0;
    if (p > 1.0)
        p = 1.0;
    double mu = (double)(n - k) * p;
    return (double)k + SFMI_CHANCE_MULT * mu + SFMI_CHANCE_SD * sqrt(mu) + SFMI_CHANCE_ADD;
}

int sfmi_above_chance(int n, int k, int n_inl, double p)
{
    return (double)n_inl >= sfmi_chance_count(n, k, p);
}

double sfmi_bbox_area(const double *p, int stride, int n, double *diag)
{
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int i = 0; i < n; i++)
        for (int c = 0; c < 2; c++) {
            double v = p[(size_t)stride * i + c];
            if (!isfinite(v) || fabs(v) > 1e8) /* unmapped points (behind a wide camera) */
                continue;
            lo[c] = v < lo[c] ? v : lo[c];
            hi[c] = v > hi[c] ? v : hi[c];
        }
    double w = hi[0] - lo[0], h = hi[1] - lo[1];
    if (!(w >= 1.0))
        w = 1.0;
    if (!(h >= 1.0))
        h = 1.0;
    if (diag != NULL)
        *diag = sqrt(w * w + h * h);
    return w * h;
}

double sfmi_chance_band(double area, double diag, double w)
{
    double p = w * diag / area;
    return p < 1.0 ? p : 1.0;
}

double sfmi_chance_disc(double area, double r)
{
    double p = 3.141592653589793 * r * r / area;
    return p < 1.0 ? p : 1.0;
}

void sfmi_spread(const double *p, int stride, const int *idx, int m, double *sd_min,
                 double *sd_max)
{
    *sd_min = 0.0;
    *sd_max = 0.0;
    if (m < 2)
        return;
    double mx = 0.0, my = 0.0;
    for (int j = 0; j < m; j++) {
        const double *q = p + (size_t)stride * (idx ? idx[j] : j);
        mx += q[0];
        my += q[1];
    }
    mx /= m;
    my /= m;
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (int j = 0; j < m; j++) {
        const double *q = p + (size_t)stride * (idx ? idx[j] : j);
        double dx = q[0] - mx, dy = q[1] - my;
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    sxx /= m;
    sxy /= m;
    syy /= m;
    /* eigenvalues of [[sxx, sxy], [sxy, syy]] */
    double tr = 0.5 * (sxx + syy), d = sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
    double l1 = tr + d, l2 = tr - d;
    *sd_max = sqrt(l1 > 0.0 ? l1 : 0.0);
    *sd_min = sqrt(l2 > 0.0 ? l2 : 0.0);
}

int sfmi_spread_collinear(double sd_min, double sd_max, double tau)
{
    return sd_min < SFMI_LINE_MULT * tau || sd_min < SFMI_LINE_RATIO * sd_max;
}

int sfmi_design_degenerate(const double *AtA, int d, int m, double s2, double *V, double *w,
                           void *ws, size_t ws_size, double small2[2])
{
    if (d < 2 || m < 1)
        return SFM_E_ARGUMENT;
    int st = sfm_sym_eig(AtA, d, w, V, ws, ws_size);
    if (st < 0)
        return st;
    /* ascending order is not promised: find the two smallest */
    double a = HUGE_VAL, b = HUGE_VAL;
    for (int i = 0; i < d; i++) {
        if (w[i] < a) {
            b = a;
            a = w[i];
        } else if (w[i] < b) {
            b = w[i];
        }
    }
    if (small2 != NULL) {
        small2[0] = a;
        small2[1] = b;
    }
    return !(b / ((double)m * (s2 > 0.0 ? s2 : 1e-300)) > SFMI_DESIGN_RHO);
}

double sfmi_block_sd(const double *cov6, int r0)
{
    double t = cov6[7 * r0] + cov6[7 * (r0 + 1)] + cov6[7 * (r0 + 2)];
    return sqrt(t > 0.0 ? t : 0.0);
}

/* Scratch of the 9 x 9 symmetric eigendecomposition. */
#define EIG9_WS 4096

int sfmi_pairs_design_degenerate(const double *g1, const double *g2, int m, int homography,
                                 double tau)
{
    double t1[3], t2[3];
    if (m < 4 || sfmi_hartley_2d(g1, m, t1) != 0 || sfmi_hartley_2d(g2, m, t2) != 0)
        return 1; /* all points on one spot */
    double AtA[81];
    memset(AtA, 0, sizeof AtA);
    int rows = 0;
    for (int j = 0; j < m; j++) {
        double x[3] = {t1[0] * g1[2 * j] + t1[1], t1[0] * g1[2 * j + 1] + t1[2], 1.0};
        double u = t2[0] * g2[2 * j] + t2[1], v = t2[0] * g2[2 * j + 1] + t2[2];
        double r[2][9];
        int nr;
        if (homography) {
            for (int c = 0; c < 3; c++) {
                r[0][c] = -x[c];
                r[0][3 + c] = 0.0;
                r[0][6 + c] = u * x[c];
                r[1][c] = 0.0;
                r[1][3 + c] = -x[c];
                r[1][6 + c] = v * x[c];
            }
            nr = 2;
        } else {
            for (int c = 0; c < 3; c++) {
                r[0][c] = u * x[c];
                r[0][3 + c] = v * x[c];
                r[0][6 + c] = x[c];
            }
            nr = 1;
        }
        for (int k = 0; k < nr; k++)
            for (int a = 0; a < 9; a++)
                for (int b = 0; b <= a; b++)
                    AtA[9 * a + b] += r[k][a] * r[k][b];
        rows += nr;
    }
    _Alignas(16) unsigned char ws[EIG9_WS];
    if (sfm_sym_eig_workspace_size(9) > sizeof ws)
        return SFM_E_WORKSPACE;
    double V[81], w[9];
    const double s = 0.5 * (t1[0] + t2[0]) * tau / 3.0;
    return sfmi_design_degenerate(AtA, 9, rows, s * s, V, w, ws, sizeof ws, NULL);
}
