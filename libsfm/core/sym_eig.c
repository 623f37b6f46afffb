/*
 * Symmetric eigendecomposition by the cyclic Jacobi method with Rutishauser's
 * rotation formulas (Golub & Van Loan, Matrix Computations, 4th ed., 8.5).
 * Jacobi is slower than tridiagonal QR for large n but simple, accurate
 * (small eigenvalues to high relative accuracy on graded matrices) and
 * deterministic; the matrices here are small. A rotation is skipped when the
 * off-diagonal entry is below eps * sqrt(|a_pp a_qq|) or below eps^2 times
 * the largest entry; convergence is a sweep without rotation.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"

#define SYM_EIG_MAX_SWEEPS 80

typedef struct sym_ws {
    double *A;  /* n x n working copy (full symmetric storage) */
    double *V;  /* n x n accumulated rotations, row-major */
    int *perm;  /* n */
} sym_ws;

static void sym_layout(sfmi_arena *a, int n, sym_ws *w)
{
    w->A = SFM_ARENA_ARRAY(a, double, (size_t)n * n);
    w->V = SFM_ARENA_ARRAY(a, double, (size_t)n * n);
    w->perm = SFM_ARENA_ARRAY(a, int, n);
}

size_t sfm_sym_eig_workspace_size(int n)
{
    if (!sfmi_la_dim_ok(n))
        return 0;
    sfmi_arena a;
    sym_ws w;
    sfmi_arena_measure(&a);
    sym_layout(&a, n, &w);
    return sfmi_arena_required(&a);
}

int sfm_sym_eig(const double *A, int n, double *w_out, double *V, void *ws, size_t ws_size)
{
    if (A == NULL || w_out == NULL || ws == NULL || !sfmi_la_dim_ok(n))
        return SFM_E_ARGUMENT;
    double maxabs = 0.0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++) {
            double v = A[(size_t)i * n + j];
            if (!isfinite(v))
                return SFM_E_NONFINITE;
            if (fabs(v) > maxabs)
                maxabs = fabs(v);
        }
    sfmi_arena ar;
    sym_ws w;
    if (ws_size < sfm_sym_eig_workspace_size(n))
        return SFM_E_WORKSPACE;
    sfmi_arena_init(&ar, ws, ws_size);
    sym_layout(&ar, n, &w);
    if (!sfmi_arena_ok(&ar))
        return SFM_E_WORKSPACE;

    const double f = sfmi_la_pow2_scale(maxabs);
    double *a = w.A;
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++)
            a[(size_t)i * n + j] = a[(size_t)j * n + i] = A[(size_t)i * n + j] * f;
    const int want_v = V != NULL;
    if (want_v) {
        memset(w.V, 0, sizeof(double) * (size_t)n * (size_t)n);
        for (int i = 0; i < n; i++)
            w.V[(size_t)i * n + i] = 1.0;
    }
    /* entries are now at most 1 in magnitude */
    const double floor_abs = DBL_EPSILON * DBL_EPSILON * (maxabs > 0.0 ? maxabs * f : 1.0);
    int converged = n == 1;
    for (int sweep = 0; sweep < SYM_EIG_MAX_SWEEPS && !converged; sweep++) {
        int rotated = 0;
        for (int p = 0; p < n - 1; p++) {
            for (int q = p + 1; q < n; q++) {
                double apq = a[(size_t)p * n + q];
                double app = a[(size_t)p * n + p], aqq = a[(size_t)q * n + q];
                if (fabs(apq) <= floor_abs ||
                    fabs(apq) <= DBL_EPSILON * sqrt(fabs(app)) * sqrt(fabs(aqq)))
                    continue;
                rotated = 1;
                double c, s;
                double t = sfmi_la_jacobi_angle((aqq - app) / (2.0 * apq), &c, &s);
                /* A <- J^T A J with J = [[c, s], [-s, c]] in the (p, q) plane */
                for (int k = 0; k < n; k++) {
                    double akp = a[(size_t)k * n + p], akq = a[(size_t)k * n + q];
                    a[(size_t)k * n + p] = c * akp - s * akq;
                    a[(size_t)k * n + q] = s * akp + c * akq;
                }
                for (int k = 0; k < n; k++) {
                    double apk = a[(size_t)p * n + k], aqk = a[(size_t)q * n + k];
                    a[(size_t)p * n + k] = c * apk - s * aqk;
                    a[(size_t)q * n + k] = s * apk + c * aqk;
                }
                a[(size_t)p * n + p] = app - t * apq;
                a[(size_t)q * n + q] = aqq + t * apq;
                a[(size_t)p * n + q] = a[(size_t)q * n + p] = 0.0;
                if (want_v)
                    for (int k = 0; k < n; k++) {
                        double vkp = w.V[(size_t)k * n + p], vkq = w.V[(size_t)k * n + q];
                        w.V[(size_t)k * n + p] = c * vkp - s * vkq;
                        w.V[(size_t)k * n + q] = s * vkp + c * vkq;
                    }
            }
        }
        if (!rotated)
            converged = 1;
    }
    if (!converged)
        return SFM_E_NO_CONVERGENCE;
    /* ascending, stable */
    for (int k = 0; k < n; k++) {
        int p = k;
        double d = a[(size_t)k * n + k];
        while (p > 0 && a[(size_t)w.perm[p - 1] * n + w.perm[p - 1]] > d) {
            w.perm[p] = w.perm[p - 1];
            p--;
        }
        w.perm[p] = k;
    }
    const double finv = 1.0 / f;
    for (int k = 0; k < n; k++)
        w_out[k] = a[(size_t)w.perm[k] * n + w.perm[k]] * finv;
    if (want_v)
        for (int i = 0; i < n; i++)
            for (int k = 0; k < n; k++)
                V[(size_t)i * n + k] = w.V[(size_t)i * n + w.perm[k]];
    return SFM_OK;
}
