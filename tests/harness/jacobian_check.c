#include "jacobian_check.h"

#include <math.h>
#include <string.h>

#define MAXN 64
#define MAXM 16

double sfm_test_verify_jacobian(sfm_test_residual_fn f, const void *user, int n, int m,
                                const double *J, double h)
{
    if (n < 1 || n > MAXN || m < 1 || m > MAXM)
        return HUGE_VAL;
    double worst = 0.0;
    for (int j = 0; j < n; j++) {
        double d[MAXN], rp[MAXM], rm[MAXM];
        memset(d, 0, sizeof d);
        d[j] = h;
        if (!f(user, d, rp))
            return HUGE_VAL;
        d[j] = -h;
        if (!f(user, d, rm))
            return HUGE_VAL;
        double dmax = 0.0, emax = 0.0;
        for (int i = 0; i < m; i++) {
            double fd = (rp[i] - rm[i]) / (2.0 * h);
            dmax = fmax(dmax, fabs(fd));
            emax = fmax(emax, fabs(fd - J[i * n + j]));
        }
        worst = fmax(worst, emax / (1.0 + dmax));
    }
    return worst;
}

typedef struct lm_probe {
    const sfmi_lm_problem *p;
    int i;
} lm_probe;

#define MAXV 64

/* the blocks' values moved by delta along their manifolds */
static int lm_probe_residual(const void *user, const double *delta, double *r)
{
    const lm_probe *pr = user;
    const sfmi_lm_problem *p = pr->p;
    double vals[MAXV];
    const double *xp[SFMI_LM_DENSE_MAX_BLOCKS];
    int vo = 0, to = 0;
    for (int b = 0; b < p->n_blocks; b++) {
        const sfmi_lm_block *B = &p->blocks[b];
        if (vo + B->size > MAXV || !sfmi_lm_block_plus(B, B->x, delta + to, vals + vo))
            return 0;
        xp[b] = vals + vo;
        vo += B->size;
        to += sfmi_lm_tangent_size(B, 1);
    }
    return p->residual(p->user, xp, pr->i, r, NULL) > 0;
}

double sfm_test_verify_lm_residual(const sfmi_lm_problem *prob, int i, double h)
{
    const int nt = sfmi_lm_tangent_size(prob->blocks, prob->n_blocks);
    const int m = prob->residual_size;
    if (nt < 1 || nt > MAXN || m > MAXM)
        return HUGE_VAL;
    double r[MAXM], J[MAXM * MAXN];
    const double *xp[SFMI_LM_DENSE_MAX_BLOCKS];
    for (int b = 0; b < prob->n_blocks; b++)
        xp[b] = prob->blocks[b].x;
    memset(J, 0, sizeof(double) * (size_t)m * nt);
    if (prob->residual(prob->user, xp, i, r, J) <= 0)
        return HUGE_VAL;
    lm_probe pr = {prob, i};
    return sfm_test_verify_jacobian(lm_probe_residual, &pr, nt, m, J, h);
}
