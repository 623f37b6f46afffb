/*
 * Gold-standard refinement for the trifocal tensor (Hartley & Zisserman,
 * 2nd ed., alg. 16.2 step (iii)): minimize the reprojection error over the
 * cameras P2, P3 and the points, P1 = [I | 0] held. Points are homogeneous
 * unit 4-vectors updated in their 3-dimensional tangent space, so points at
 * infinity of the projective frame need no special case. The projective
 * gauge left after fixing P1 (4 DOF) and the camera scales are absorbed by
 * the additive LM damping; cameras are rescaled to unit norm after each step.
 */
#include "robust/trifocal_refine.h"

#include <math.h>
#include <string.h>

#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_trifocal.h"
#include "solvers/trifocal_internal.h"

enum { NC = 24 };

void sfm_tf_refine_layout(sfm_arena *a, int n, sfm_tf_refine_ws *w)
{
    w->X = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    w->Xold = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    w->cap = n;
}

static const double P1[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

static double total_cost(const double *const xs[3], const int *idx, int n, const double *P2,
                         const double *P3, const double *X)
{
    const double *P[3] = {P1, P2, P3};
    double c = 0;
    for (int q = 0; q < n; q++) {
        int p = idx[q];
        for (int v = 0; v < 3; v++) {
            double r[2];
            if (!sfm_trifocal_residual(P[v], &X[4 * q], &xs[v][2 * p], r, NULL, NULL))
                return HUGE_VAL;
            c += r[0] * r[0] + r[1] * r[1];
        }
    }
    return c;
}

/* Per-point blocks: Jp (6x3), Jc rows (view 2 -> cols 0..11, view 3 -> 12..23)
 * stored as two 2x12 blocks, residual r (6). */
typedef struct point_blocks {
    double Jp[18], Jc2[24], Jc3[24], r[6];
} point_blocks;

static int point_jacobians(const double *const xs[3], int p, const double *P2, const double *P3,
                           const double X[4], point_blocks *b)
{
    const double *P[3] = {P1, P2, P3};
    double B[12];
    sfm_trifocal_tangent_basis(X, B);
    for (int v = 0; v < 3; v++) {
        double JX[8];
        double *JP = v == 1 ? b->Jc2 : v == 2 ? b->Jc3 : NULL;
        if (!sfm_trifocal_residual(P[v], X, &xs[v][2 * p], &b->r[2 * v], JX, JP))
            return 0;
        for (int h = 0; h < 2; h++)
            for (int c = 0; c < 3; c++)
                b->Jp[(2 * v + h) * 3 + c] = JX[h * 4] * B[c] + JX[h * 4 + 1] * B[3 + c] +
                                             JX[h * 4 + 2] * B[6 + c] + JX[h * 4 + 3] * B[9 + c];
    }
    return 1;
}

/* W = Jc^T Jp (24x3), g_c contribution Jc^T r (24), V = Jp^T Jp (3x3), gp. */
static void point_products(const point_blocks *b, double W[72], double gc[24], double V[9],
                           double gp[3])
{
    for (int a = 0; a < 3; a++) {
        gp[a] = 0;
        for (int k = 0; k < 6; k++)
            gp[a] += b->Jp[k * 3 + a] * b->r[k];
        for (int c = 0; c < 3; c++) {
            double s = 0;
            for (int k = 0; k < 6; k++)
                s += b->Jp[k * 3 + a] * b->Jp[k * 3 + c];
            V[a * 3 + c] = s;
        }
    }
    for (int j = 0; j < 12; j++) {
        /* view 2 rows 2,3 of Jp; view 3 rows 4,5 */
        for (int c = 0; c < 3; c++) {
            W[j * 3 + c] = b->Jc2[j] * b->Jp[2 * 3 + c] + b->Jc2[12 + j] * b->Jp[3 * 3 + c];
            W[(12 + j) * 3 + c] = b->Jc3[j] * b->Jp[4 * 3 + c] + b->Jc3[12 + j] * b->Jp[5 * 3 + c];
        }
        gc[j] = b->Jc2[j] * b->r[2] + b->Jc2[12 + j] * b->r[3];
        gc[12 + j] = b->Jc3[j] * b->r[4] + b->Jc3[12 + j] * b->r[5];
    }
}

/* Inverse of a symmetric positive definite 3x3 by cofactors. */
static int inv3(const double A[9], double Ai[9])
{
    double c0 = A[4] * A[8] - A[5] * A[7], c1 = A[5] * A[6] - A[3] * A[8], c2 = A[3] * A[7] - A[4] * A[6];
    double det = A[0] * c0 + A[1] * c1 + A[2] * c2;
    if (!(fabs(det) > 1e-300))
        return 0;
    double id = 1.0 / det;
    Ai[0] = c0 * id;
    Ai[1] = (A[2] * A[7] - A[1] * A[8]) * id;
    Ai[2] = (A[1] * A[5] - A[2] * A[4]) * id;
    Ai[3] = c1 * id;
    Ai[4] = (A[0] * A[8] - A[2] * A[6]) * id;
    Ai[5] = (A[2] * A[3] - A[0] * A[5]) * id;
    Ai[6] = c2 * id;
    Ai[7] = (A[1] * A[6] - A[0] * A[7]) * id;
    Ai[8] = (A[0] * A[4] - A[1] * A[3]) * id;
    return 1;
}

static void normalize12(double *P)
{
    double s = 0;
    for (int k = 0; k < 12; k++)
        s += P[k] * P[k];
    s = sqrt(s);
    if (s > 0)
        for (int k = 0; k < 12; k++)
            P[k] /= s;
}

double sfm_tf_refine(const double *x1, const double *x2, const double *x3, const int *idx, int n,
                     double P2[12], double P3[12], int max_iters, sfm_tf_refine_ws *w, int *status)
{
    const double *xs[3] = {x1, x2, x3};
    *status = SFM_OK;
    if (n > w->cap || n < SFM_TRIFOCAL_MIN_POINTS) {
        *status = SFM_E_ARGUMENT;
        return HUGE_VAL;
    }
    double A2[12], A3[12];
    memcpy(A2, P2, sizeof A2);
    memcpy(A3, P3, sizeof A3);
    normalize12(A2);
    normalize12(A3);
    /* Initial points: optimal triangulation under the current cameras. */
    for (int q = 0; q < n; q++) {
        int p = idx[q];
        double e;
        int st = sfm_trifocal_point_error(P1, A2, A3, &x1[2 * p], &x2[2 * p], &x3[2 * p], &e, &w->X[4 * q]);
        if (st < 0) {
            *status = st;
            return HUGE_VAL;
        }
    }
    double cost = total_cost(xs, idx, n, A2, A3, w->X);
    if (!isfinite(cost)) {
        *status = SFM_E_SINGULAR;
        return HUGE_VAL;
    }
    double lambda = 1e-4;
    for (int it = 0; it < max_iters; it++) {
        double S[NC * NC], g[NC], Udiag[NC];
        memset(S, 0, sizeof S);
        memset(Udiag, 0, sizeof Udiag);
        memset(g, 0, sizeof g);
        /* Pass 1: reduced camera system S dc = -g_red. */
        for (int q = 0; q < n; q++) {
            point_blocks b;
            if (!point_jacobians(xs, idx[q], A2, A3, &w->X[4 * q], &b))
                continue;
            double W[72], gc[24], V[9], gp[3], Vi[9];
            point_products(&b, W, gc, V, gp);
            for (int k = 0; k < 3; k++)
                V[k * 4] *= 1.0 + lambda;
            if (!inv3(V, Vi))
                continue;
            /* U block: Jc^T Jc is block diagonal (view 2, view 3) */
            for (int a = 0; a < 12; a++)
                for (int c = 0; c < 12; c++) {
                    S[a * NC + c] += b.Jc2[a] * b.Jc2[c] + b.Jc2[12 + a] * b.Jc2[12 + c];
                    S[(12 + a) * NC + 12 + c] += b.Jc3[a] * b.Jc3[c] + b.Jc3[12 + a] * b.Jc3[12 + c];
                }
            for (int a = 0; a < 12; a++) {
                Udiag[a] += b.Jc2[a] * b.Jc2[a] + b.Jc2[12 + a] * b.Jc2[12 + a];
                Udiag[12 + a] += b.Jc3[a] * b.Jc3[a] + b.Jc3[12 + a] * b.Jc3[12 + a];
            }
            double WVi[72];
            for (int a = 0; a < NC; a++)
                for (int c = 0; c < 3; c++)
                    WVi[a * 3 + c] = W[a * 3] * Vi[c] + W[a * 3 + 1] * Vi[3 + c] + W[a * 3 + 2] * Vi[6 + c];
            for (int a = 0; a < NC; a++) {
                for (int c = 0; c < NC; c++)
                    S[a * NC + c] -= WVi[a * 3] * W[c * 3] + WVi[a * 3 + 1] * W[c * 3 + 1] +
                                     WVi[a * 3 + 2] * W[c * 3 + 2];
                g[a] += gc[a] - (WVi[a * 3] * gp[0] + WVi[a * 3 + 1] * gp[1] + WVi[a * 3 + 2] * gp[2]);
            }
        }
        /* Marquardt damping of the camera block: lambda scales the diagonal
         * of U (the Schur complement's own diagonal can vanish along the
         * gauge directions). */
        for (int a = 0; a < NC; a++) {
            S[a * NC + a] += lambda * Udiag[a] + 1e-12 * (Udiag[a] + 1.0);
            g[a] = -g[a];
        }
        if (sfm_cholesky_factor(S, NC) != SFM_OK || sfm_cholesky_solve(S, NC, g, 1) != SFM_OK) {
            lambda *= 10;
            continue;
        }
        /* Pass 2: back-substitute the points and try the step. */
        double B2[12], B3[12];
        for (int k = 0; k < 12; k++) {
            B2[k] = A2[k] + g[k];
            B3[k] = A3[k] + g[12 + k];
        }
        memcpy(w->Xold, w->X, sizeof(double) * 4 * (size_t)n);
        for (int q = 0; q < n; q++) {
            point_blocks b;
            double *X = &w->X[4 * q];
            if (!point_jacobians(xs, idx[q], A2, A3, X, &b))
                continue;
            double W[72], gc[24], V[9], gp[3], Vi[9], rhs[3], d[3], B[12];
            point_products(&b, W, gc, V, gp);
            for (int k = 0; k < 3; k++)
                V[k * 4] *= 1.0 + lambda;
            if (!inv3(V, Vi))
                continue;
            for (int c = 0; c < 3; c++) {
                rhs[c] = -gp[c];
                for (int a = 0; a < NC; a++)
                    rhs[c] -= W[a * 3 + c] * g[a];
            }
            for (int c = 0; c < 3; c++)
                d[c] = Vi[c * 3] * rhs[0] + Vi[c * 3 + 1] * rhs[1] + Vi[c * 3 + 2] * rhs[2];
            sfm_trifocal_tangent_basis(X, B);
            double nn = 0;
            for (int r = 0; r < 4; r++) {
                X[r] += B[r * 3] * d[0] + B[r * 3 + 1] * d[1] + B[r * 3 + 2] * d[2];
                nn += X[r] * X[r];
            }
            nn = sqrt(nn);
            for (int r = 0; r < 4; r++)
                X[r] /= nn;
        }
        double c1 = total_cost(xs, idx, n, B2, B3, w->X);
        if (c1 < cost) {
            double gain = cost - c1;
            normalize12(B2);
            normalize12(B3);
            memcpy(A2, B2, sizeof A2);
            memcpy(A3, B3, sizeof A3);
            cost = c1;
            lambda = lambda * 0.1 > 1e-12 ? lambda * 0.1 : 1e-12;
            if (gain < 1e-10 * (1.0 + cost))
                break;
        } else {
            memcpy(w->X, w->Xold, sizeof(double) * 4 * (size_t)n);
            lambda *= 10;
            if (lambda > 1e8)
                break;
        }
    }
    memcpy(P2, A2, sizeof A2);
    memcpy(P3, A3, sizeof A3);
    return cost;
}
