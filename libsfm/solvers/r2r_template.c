/*
 * The shared back end of the generated action-matrix solvers
 * (libsfm/solvers/generated/r2r_tmpl_*.c, tools/gen_r2r_templates.py).
 *
 * Template rows: A [e; r] + X0 b = 0 over the kept excessive and reducible
 * monomials (A square) and the basis b. Solving A Y = X0 gives the normal
 * form of each reducible monomial r = -Y_r b. Row j of the action matrix M
 * holds a * b_j on the basis, so M B(x) = a(x) B(x): every right eigenvector
 * is the basis evaluated at one solution, up to scale.
 * sfmi_tmpl_run scatters a generated file's coefficients into A and X from
 * its entry tables, so each generated file holds only data and the
 * coefficient expressions.
 */
#include <math.h>

#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"
#include "solvers/generated/r2r_tmpl.h"

/* An eigenvalue is real when its imaginary part is below this share of its
 * modulus (plus one): near-double real roots split into tiny pairs. */
#define REAL_TOL 1e-8

int sfmi_tmpl_run(const sfmi_tmpl *T, const double *c, double *A, int *piv, double *X,
                  double *M, double *V, double *wr, double *wi, double *ews, size_t ews_size,
                  double *sol)
{
    int nk = T->nk, nb = T->nb;
    for (int i = 0; i < nk * nk; i++)
        A[i] = 0.0;
    for (int i = 0; i < nk * nb; i++)
        X[i] = 0.0;
    for (int i = 0; i < T->n_a; i++)
        A[T->a_ent[i][0] * nk + T->a_ent[i][1]] = c[T->a_ent[i][2]];
    for (int i = 0; i < T->n_b; i++)
        X[T->b_ent[i][0] * nb + T->b_ent[i][1]] = c[T->b_ent[i][2]];
    return sfmi_tmpl_finish(A, piv, nk, X, nb, T->act_src, T->var_src, T->nx, T->one, M, V, wr,
                            wi, ews, ews_size, sol);
}

int sfmi_tmpl_finish(double *A, int *piv, int nk, double *X, int nb,
                     const short *act_src, const short *var_src, int nx, int one,
                     double *M, double *V, double *wr, double *wi, double *ews,
                     size_t ews_size /* bytes */, double *sol)
{
    int st = sfm_lu_factor(A, nk, piv);
    if (st < 0)
        return st;
    double umax = 0.0, umin = HUGE_VAL;
    for (int i = 0; i < nk; i++) {
        double u = fabs(A[i * nk + i]);
        umax = u > umax ? u : umax;
        umin = u < umin ? u : umin;
    }
    if (!(umin > 1e-14 * umax))
        return SFM_E_SINGULAR;
    /* The action matrix reads only the reduced rows of the solution, the
     * last unknowns of the template: substitute forward in full, backward
     * only down to the first row read. */
    int r0 = nk;
    for (int j = 0; j < nb; j++)
        if (act_src[j] < 0 && -1 - act_src[j] < r0)
            r0 = -1 - act_src[j];
    for (int k = 0; k < nk; k++)
        if (piv[k] != k)
            for (int j = 0; j < nb; j++) {
                double t = X[k * nb + j];
                X[k * nb + j] = X[piv[k] * nb + j];
                X[piv[k] * nb + j] = t;
            }
    for (int i = 1; i < nk; i++)
        for (int k = 0; k < i; k++) {
            double l = A[i * nk + k];
            if (l != 0.0)
                for (int j = 0; j < nb; j++)
                    X[i * nb + j] -= l * X[k * nb + j];
        }
    for (int i = nk - 1; i >= r0; i--) {
        for (int k = i + 1; k < nk; k++) {
            double u = A[i * nk + k];
            if (u != 0.0)
                for (int j = 0; j < nb; j++)
                    X[i * nb + j] -= u * X[k * nb + j];
        }
        double inv = 1.0 / A[i * nk + i];
        for (int j = 0; j < nb; j++)
            X[i * nb + j] *= inv;
    }
    for (int j = 0; j < nb; j++) {
        int s = act_src[j];
        for (int k = 0; k < nb; k++)
            M[j * nb + k] = s >= 0 ? (k == s ? 1.0 : 0.0) : -X[(-1 - s) * nb + k];
    }
    st = sfm_eig(M, nb, wr, wi, V, ews, ews_size);
    if (st < 0)
        return st;
    int n = 0;
    for (int k = 0; k < nb; k++) {
        if (fabs(wi[k]) > REAL_TOL * (1.0 + fabs(wr[k])))
            continue;
        double v1 = V[one * nb + k];
        if (!(fabs(v1) > 1e-300))
            continue;
        int ok = 1;
        for (int i = 0; i < nx; i++) {
            double x = var_src[i] < 0 ? wr[k] : V[var_src[i] * nb + k] / v1;
            ok &= isfinite(x);
            sol[n * nx + i] = x;
        }
        n += ok;
    }
    return n;
}
