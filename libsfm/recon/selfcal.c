/*
 * Linear self-calibration by the absolute dual quadric (see sfm_selfcal.h).
 * Q* is parameterized by its 10 upper-triangular entries in the order
 * (00, 01, 02, 03, 11, 12, 13, 22, 23, 33).
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_selfcal.h"
#include "recon/selfcal_internal.h"

/* weights of Pollefeys et al.: zero skew and principal point 1/0.1, unit
 * aspect 1/0.2, focal near the guess 1/9 */
#define W_STRONG (1.0 / 0.1)
#define W_ASPECT (1.0 / 0.2)
#define W_WEAK (1.0 / 9.0)
/* second null direction of the strong equations: a critical motion */
#define AMBIGUOUS_RATIO 0.2
/* The weak equations moved the solution along a direction the strong ones
 * leave nearly free: the strong residual of the solution with the weak
 * equations over the strong minimum (both at that solve's weights), and
 * the mean relative change of f it made per unit of that ratio. Measured
 * (factorized tracks, 3-8 views, 0.1-2 px, 432 turntables over 17-172 deg,
 * 144 general scenes): when the strong solution is unusable and the prior
 * rescues it, a turntable's ratio is 2.6 or more (general motion never
 * came there); with a usable strong solution, a turntable's change per
 * ratio is 0.43 or more at ratios above 4, general motion's 0.011 or less
 * (on exact data the prior moves a usable solution at no cost to the data:
 * a 3-view case 3.8 % at a ratio of 153). */
#define WEAK_RATIO_RESCUE 2.0
#define WEAK_RATIO_USABLE 4.0
#define WEAK_SHIFT_MAX 0.05
#define FRONT_MIN 0.9

static const int QI[10] = {0, 0, 0, 0, 1, 1, 1, 2, 2, 3};
static const int QJ[10] = {0, 1, 2, 3, 1, 2, 3, 2, 3, 3};

/* coefficients of w_ab = (P Q P^T)_ab in the 10 entries of Q */
void sfmi_selfcal_omega_row(const double P[12], int a, int b, double r[10])
{
    for (int k = 0; k < 10; k++) {
        int i = QI[k], j = QJ[k];
        r[k] = P[4 * a + i] * P[4 * b + j];
        if (i != j)
            r[k] += P[4 * a + j] * P[4 * b + i];
    }
}

void sfmi_selfcal_add_row(double A[100], const double r[10], double w)
{
    for (int a = 0; a < 10; a++)
        for (int b = 0; b <= a; b++)
            A[a * 10 + b] += w * w * r[a] * r[b];
}

/* W = P Q P^T (3x3) */
void sfmi_selfcal_omega(const double P[12], const double Q[16], double W[9])
{
    double PQ[12];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += P[4 * r + k] * Q[4 * k + c];
            PQ[4 * r + c] = s;
        }
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += PQ[4 * r + k] * P[4 * c + k];
            W[3 * r + c] = s;
        }
}

void sfmi_selfcal_set_q(const double q[10], int m, const double Pc[][12], double Q[16], double *nu)
{
    for (int k = 0; k < 10; k++)
        Q[4 * QI[k] + QJ[k]] = Q[4 * QJ[k] + QI[k]] = q[k];
    /* sign: Q* is positive semi-definite, so its trace is positive */
    if (Q[0] + Q[5] + Q[10] + Q[15] < 0)
        for (int k = 0; k < 16; k++)
            Q[k] = -Q[k];
    for (int i = 0; i < m; i++) {
        double W[9];
        sfmi_selfcal_omega(Pc[i], Q, W);
        nu[i] = fabs(W[8]) > 1e-12 ? fabs(W[8]) : 1.0;
    }
}

/* Upper-triangular K with K K^T = W (W positive definite, scaled so
 * K_22 = 1). 0 when W is not positive definite. */
int sfmi_selfcal_upper_cholesky(const double Win[9], double K[9])
{
    if (!(Win[8] > 0))
        return 0;
    double W[9];
    for (int k = 0; k < 9; k++)
        W[k] = Win[k] / Win[8];
    double cx = W[2], cy = W[5];
    double fy2 = W[4] - cy * cy;
    if (!(fy2 > 0))
        return 0;
    double fy = sqrt(fy2);
    double s = (W[1] - cx * cy) / fy;
    double fx2 = W[0] - cx * cx - s * s;
    if (!(fx2 > 0))
        return 0;
    const double k[9] = {sqrt(fx2), s, cx, 0, fy, cy, 0, 0, 1};
    memcpy(K, k, sizeof k);
    return 1;
}

double sfmi_selfcal_det3(const double M[9])
{
    return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
           M[2] * (M[3] * M[7] - M[4] * M[6]);
}

/* C (rows x 4) = A (rows x 4) B (4x4) */
static void mul_rows_44(int rows, const double *A, const double B[16], double *C)
{
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += A[4 * r + k] * B[4 * k + c];
            C[4 * r + c] = s;
        }
}

void sfmi_selfcal_mul44(const double A[16], const double B[16], double C[16])
{
    mul_rows_44(4, A, B, C);
}

void sfmi_selfcal_mul34_44(const double P[12], const double H[16], double out[12])
{
    mul_rows_44(3, P, H, out);
}

void sfmi_selfcal_adq_rows(const double P[12], double r[6][10])
{
    double r00[10], r11[10], r22[10];
    sfmi_selfcal_omega_row(P, 0, 0, r00);
    sfmi_selfcal_omega_row(P, 1, 1, r11);
    sfmi_selfcal_omega_row(P, 2, 2, r22);
    sfmi_selfcal_omega_row(P, 0, 1, r[0]);
    sfmi_selfcal_omega_row(P, 0, 2, r[1]);
    sfmi_selfcal_omega_row(P, 1, 2, r[2]);
    for (int k = 0; k < 10; k++) {
        r[3][k] = r00[k] - r11[k];
        r[4][k] = r00[k] - r22[k];
        r[5][k] = r11[k] - r22[k];
    }
}

void sfmi_selfcal_condition(const double P[12], double cx, double cy, double s, double out[12])
{
    for (int k = 0; k < 4; k++) {
        out[k] = (P[k] - cx * P[8 + k]) / s;
        out[4 + k] = (P[4 + k] - cy * P[8 + k]) / s;
        out[8 + k] = P[8 + k];
    }
}

void sfmi_selfcal_scale_cameras(int m, const double *P, double *Ps)
{
    const double lo = 1.0 / 1048576.0, hi = 1099511627776.0; /* 2^-20, 2^40 */
    for (int i = 0; i < m; i++) {
        const double *Pi = &P[12 * i];
        double *Qi = &Ps[12 * i];
        double a = 0;
        for (int k = 0; k < 12; k++) {
            Qi[k] = Pi[k];
            a = fmax(a, fabs(Pi[k]));
        }
        if (!(a > 0) || (a >= lo && a <= hi))
            continue;
        /* the doublings (or halvings) taking a into [1, 2): up to 1075 for
         * a subnormal, applied 2^256 at a time (2^1074 is not a double) */
        int e = 0;
        for (; a < 1; a *= 2)
            e++;
        for (; a >= 2; a *= 0.5)
            e--;
        while (e != 0) {
            const int step = e > 256 ? 256 : (e < -256 ? -256 : e);
            double f = 1;
            for (int k = 0; k < (step > 0 ? step : -step); k++)
                f *= step > 0 ? 2.0 : 0.5;
            for (int k = 0; k < 12; k++)
                Qi[k] *= f;
            e -= step;
        }
    }
}

/* A = B^{-1} for 4x4 by LU (copy). 0 when singular. */
int sfmi_selfcal_inv44(const double B[16], double A[16])
{
    double LU[16];
    int piv[4];
    memcpy(LU, B, sizeof LU);
    if (sfm_lu_factor(LU, 4, piv) < 0)
        return 0;
    for (int k = 0; k < 16; k++)
        A[k] = (k % 5 == 0) ? 1.0 : 0.0;
    if (sfm_lu_solve(LU, piv, 4, A, 4) < 0)
        return 0;
    return sfmi_la_all_finite(A, 16);
}

int sfmi_selfcal_rank3(double Q[16], int *flags, void *ews, size_t ews_size)
{
    double ev[4], V[16];
    int st = sfm_sym_eig(Q, 4, ev, V, ews, ews_size);
    if (st < 0)
        return st;
    int small = 0;
    for (int k = 1; k < 4; k++)
        if (fabs(ev[k]) < fabs(ev[small]))
            small = k;
    int pos = 0, neg = 0;
    for (int k = 0; k < 4; k++)
        if (k != small)
            pos += ev[k] > 0, neg += ev[k] < 0;
    double sgn = pos >= neg ? 1.0 : -1.0;
    if (pos != 3 && neg != 3)
        *flags |= SFM_SELFCAL_FLAG_NOT_PSD;
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                if (k != small)
                    s += V[4 * a + k] * sgn * ev[k] * V[4 * b + k];
            Q[4 * a + b] = s;
        }
    return SFM_OK;
}

static double quad10(const double A[100], const double q[10])
{
    double s = 0;
    for (int a = 0; a < 10; a++) {
        s += A[a * 10 + a] * q[a] * q[a];
        for (int b = 0; b < a; b++)
            s += 2 * A[a * 10 + b] * q[a] * q[b];
    }
    return s;
}

/* One weighted linear solve (two passes), rank 3, semi-definiteness and
 * the focal lengths; flags in res. *weak_ratio: sqrt(q^T A_strong q /
 * lambda_min(A_strong)) at the last pass (1 without the weak equations, up
 * to rounding). */
static int solve_adq(int m, double Pc[][12], const double *sc, int weak, double Q[16], double K1[9],
                     sfm_selfcal_result *res, double *weak_ratio, void *ews, size_t ews_size)
{
    /* two passes: unit weights, then rows divided by each view's w_22 */
    double nu[SFM_SELFCAL_MAX_VIEWS], q[10];
    int st;
    for (int i = 0; i < m; i++)
        nu[i] = 1;
    for (int pass = 0; pass < 2; pass++) {
        double Aall[100] = {0}, Astrong[100] = {0};
        for (int i = 0; i < m; i++) {
            double r[6][10];
            sfmi_selfcal_adq_rows(Pc[i], r);
            double iw = 1.0 / nu[i];
            sfmi_selfcal_add_row(Astrong, r[3], W_ASPECT * iw);
            for (int k = 0; k < 3; k++)
                sfmi_selfcal_add_row(Astrong, r[k], W_STRONG * iw);
            sfmi_selfcal_add_row(Aall, r[4], W_WEAK * iw);
            sfmi_selfcal_add_row(Aall, r[5], W_WEAK * iw);
        }
        for (int k = 0; k < 100; k++)
            Aall[k] = weak ? Aall[k] + Astrong[k] : Astrong[k];
        double w10[10], V10[100];
        st = sfm_sym_eig(Astrong, 10, w10, V10, ews, ews_size);
        if (st < 0)
            return st;
        res->null_ratio = w10[1] > 0 ? sqrt(fmax(w10[0], 0) / w10[1]) : 1.0;
        if (!(w10[1] > 1e-12 * w10[9]))
            res->null_ratio = 1.0;
        /* the strong minimum, floored at a singular value 1e-6 of the
         * largest (rounding on exact data; a turntable's minimum at 0.5 px
         * is 9e-5 of it) */
        const double lmin = fmax(w10[0], 1e-12 * w10[9]);
        st = sfm_sym_eig(Aall, 10, w10, V10, ews, ews_size);
        if (st < 0)
            return st;
        for (int k = 0; k < 10; k++)
            q[k] = V10[k * 10];
        {
            double c = quad10(Astrong, q);
            *weak_ratio = lmin > 0 ? sqrt(fmax(c, 0) / lmin) : 1.0;
        }
        sfmi_selfcal_set_q(q, m, (const double(*)[12])Pc, Q, nu);
    }
    if (res->null_ratio > AMBIGUOUS_RATIO)
        res->flags |= SFM_SELFCAL_FLAG_AMBIGUOUS;

    st = sfmi_selfcal_rank3(Q, &res->flags, ews, ews_size);
    if (st < 0)
        return st;
    /* every w*_i positive definite: the focal lengths */
    for (int i = 0; i < m; i++) {
        double W[9], Ki[9];
        sfmi_selfcal_omega(Pc[i], Q, W);
        if (!sfmi_selfcal_upper_cholesky(W, Ki)) {
            res->flags |= SFM_SELFCAL_FLAG_OMEGA_NOT_PD;
            res->focal[i] = 0;
            continue;
        }
        if (i == 0)
            memcpy(K1, Ki, 9 * sizeof(double));
        res->focal[i] = 0.5 * (Ki[0] + Ki[4]) * sc[i];
    }
    return SFM_OK;
}

int sfmi_selfcal_frame(int m, double Pc[][12], double H0[16], void *ews, size_t ews_size)
{
    /* H0 = [Pn_1; C^T]^{-1} puts the first camera at [I | 0] */
    double G[16] = {0}, ev[4], V[16];
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
            for (int r = 0; r < 3; r++)
                G[4 * a + b] += Pc[0][4 * r + a] * Pc[0][4 * r + b];
    int st = sfm_sym_eig(G, 4, ev, V, ews, ews_size);
    if (st < 0)
        return st;
    if (!(ev[1] > 1e-12 * ev[3]))
        return SFM_E_SINGULAR;
    double A4[16];
    memcpy(A4, Pc[0], 12 * sizeof(double));
    for (int k = 0; k < 4; k++)
        A4[12 + k] = V[4 * k];
    if (!sfmi_selfcal_inv44(A4, H0))
        return SFM_E_SINGULAR;
    for (int i = 0; i < m; i++) {
        double t[12];
        sfmi_selfcal_mul34_44(Pc[i], H0, t);
        memcpy(Pc[i], t, sizeof t);
    }
    /* balance the fourth coordinate against the first three */
    double num = 0, den = 0;
    for (int i = 1; i < m; i++)
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                num += Pc[i][4 * r + c] * Pc[i][4 * r + c];
            den += Pc[i][4 * r + 3] * Pc[i][4 * r + 3];
        }
    double lam = den > 1e-30 * num ? sqrt(num / (3 * den)) : 1.0;
    for (int i = 0; i < m; i++)
        for (int r = 0; r < 3; r++)
            Pc[i][4 * r + 3] *= lam;
    for (int r = 0; r < 4; r++)
        H0[4 * r + 3] *= lam;
    for (int i = 0; i < m; i++) {
        double s = 0;
        for (int k = 0; k < 12; k++)
            s += Pc[i][k] * Pc[i][k];
        s = 1 / sqrt(s);
        for (int k = 0; k < 12; k++)
            Pc[i][k] *= s;
    }
    return SFM_OK;
}

int sfmi_selfcal_rectify(int m, const double *P, const double Q[16], const double K1[9], const double H0[16],
                         int n, const double *X, double Ht[16], sfm_selfcal_result *res)
{
    /* plane at infinity p from Q* = [w1, -w1 p; -p^T w1, p^T w1 p] with
     * w1 = K1 K1^T (P_1 = [I | 0]), w1 taken at Q's own scale */
    double LU[9], pinf[3];
    int piv[3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            LU[3 * r + c] = Q[4 * r + c];
    for (int r = 0; r < 3; r++)
        pinf[r] = -Q[4 * r + 3];
    if (sfm_lu_factor(LU, 3, piv) < 0 || sfm_lu_solve(LU, piv, 3, pinf, 1) < 0)
        return SFM_E_SINGULAR;
    double H1[16] = {0};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            H1[4 * r + c] = K1[3 * r + c];
    for (int c = 0; c < 3; c++)
        H1[12 + c] = -(pinf[0] * K1[c] + pinf[1] * K1[3 + c] + pinf[2] * K1[6 + c]);
    H1[15] = 1;
    sfmi_selfcal_mul44(H0, H1, Ht);

    /* mirror by cheirality */
    long front = 0, total = 0;
    if (n > 0) {
        double Hi[16];
        if (!sfmi_selfcal_inv44(Ht, Hi))
            return SFM_E_SINGULAR;
        double dets[SFM_SELFCAL_MAX_VIEWS];
        for (int i = 0; i < m; i++) {
            double Pm[12], M[9];
            sfmi_selfcal_mul34_44(&P[12 * i], Ht, Pm);
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    M[3 * r + c] = Pm[4 * r + c];
            dets[i] = sfmi_selfcal_det3(M);
        }
        for (int j = 0; j < n; j++) {
            const double *Xj = &X[4 * (size_t)j];
            if (Xj[0] == 0 && Xj[1] == 0 && Xj[2] == 0 && Xj[3] == 0)
                continue;
            double T = Hi[12] * Xj[0] + Hi[13] * Xj[1] + Hi[14] * Xj[2] + Hi[15] * Xj[3];
            for (int i = 0; i < m; i++) {
                const double *Pi = &P[12 * i];
                double w = Pi[8] * Xj[0] + Pi[9] * Xj[1] + Pi[10] * Xj[2] + Pi[11] * Xj[3];
                front += dets[i] * w * T > 0;
                total++;
            }
        }
        if (total > 0 && 2 * front < total) {
            for (int r = 0; r < 4; r++)
                Ht[4 * r + 3] = -Ht[4 * r + 3];
            front = total - front;
            res->flags |= SFM_SELFCAL_FLAG_MIRRORED;
        }
        res->front_fraction = total > 0 ? (double)front / (double)total : 0.0;
        if (total > 0 && res->front_fraction < FRONT_MIN) {
            res->flags |= SFM_SELFCAL_FLAG_CHEIRALITY;
            return SFM_E_SINGULAR;
        }
    }
    if (!sfmi_la_all_finite(Ht, 16))
        return SFM_E_SINGULAR;
    return SFM_OK;
}

int sfm_selfcal_linear(int m, const double *P, const double *wh, int n, const double *X, double *K,
                       double H[16], sfm_selfcal_result *result)
{
    if (P == NULL || wh == NULL || K == NULL || H == NULL || m < 3 || m > SFM_SELFCAL_MAX_VIEWS ||
        n < 0 || (n > 0 && X == NULL))
        return SFM_E_ARGUMENT;
    for (int i = 0; i < m; i++)
        if (!(wh[2 * i] > 0) || !(wh[2 * i + 1] > 0))
            return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(P, 12 * (size_t)m) || !sfmi_la_all_finite(wh, 2 * (size_t)m) ||
        (n > 0 && !sfmi_la_all_finite(X, 4 * (size_t)n)))
        return SFM_E_NONFINITE;
    unsigned char ews[2048]; /* sfm_sym_eig for n <= 10: 1663 bytes measured */
    if (sfm_sym_eig_workspace_size(10) > sizeof ews)
        return SFM_E_WORKSPACE; /* cannot happen: the 10x10 eigensolver is small */
    double Pscaled[12 * SFM_SELFCAL_MAX_VIEWS];
    sfmi_selfcal_scale_cameras(m, P, Pscaled);
    P = Pscaled;

    sfm_selfcal_result res;
    memset(&res, 0, sizeof res);

    /* conditioned cameras Pn_i = N_i P_i */
    double Pc[SFM_SELFCAL_MAX_VIEWS][12], sc[SFM_SELFCAL_MAX_VIEWS];
    for (int i = 0; i < m; i++) {
        double s = 0.5 * (wh[2 * i] + wh[2 * i + 1]);
        double cx = 0.5 * (wh[2 * i] - 1), cy = 0.5 * (wh[2 * i + 1] - 1);
        sc[i] = s;
        sfmi_selfcal_condition(&P[12 * i], cx, cy, s, Pc[i]);
    }
    double H0[16];
    int st = sfmi_selfcal_frame(m, Pc, H0, ews, sizeof ews);
    if (st < 0)
        return st;

    /* The strong equations alone (exact on exact data) and again with the
     * weak focal prior added. The strong solution is the answer when
     * usable, else the one with the prior; either way the prior must not
     * have chosen it. When the solution with the prior leaves the strong
     * equations far above their minimum (and, with a usable strong
     * solution, moved the focal lengths that far), the strong block has a
     * second, nearly free direction that the prior resolved (orbital
     * motion, critical for per-view focal lengths: Sturm 1997; Kahl,
     * Triggs and Astrom 2000) and the answer is refused as ambiguous. */
    double Q[16], K1[9], Qw[16], K1w[9], ratio_s, ratio_w; /* ratio_s unused (1) */
    const int unusable = SFM_SELFCAL_FLAG_NOT_PSD | SFM_SELFCAL_FLAG_OMEGA_NOT_PD;
    sfm_selfcal_result rw = res;
    st = solve_adq(m, Pc, sc, 0, Q, K1, &res, &ratio_s, ews, sizeof ews);
    if (st < 0)
        return st;
    st = solve_adq(m, Pc, sc, 1, Qw, K1w, &rw, &ratio_w, ews, sizeof ews);
    if (st < 0)
        return st;
    if (!(res.flags & unusable)) {
        double shift = 0;
        if (rw.flags & unusable)
            shift = HUGE_VAL;
        else
            for (int i = 0; i < m; i++)
                shift += fabs(rw.focal[i] / res.focal[i] - 1) / m;
        if (ratio_w > WEAK_RATIO_USABLE && shift / ratio_w > WEAK_SHIFT_MAX)
            res.flags |= SFM_SELFCAL_FLAG_AMBIGUOUS;
    } else {
        res = rw;
        memcpy(Q, Qw, sizeof Q);
        memcpy(K1, K1w, sizeof K1);
        if (ratio_w > WEAK_RATIO_RESCUE)
            res.flags |= SFM_SELFCAL_FLAG_AMBIGUOUS;
    }
    res.weak_ratio = ratio_w;
    if (res.flags & (SFM_SELFCAL_FLAG_NOT_PSD | SFM_SELFCAL_FLAG_OMEGA_NOT_PD | SFM_SELFCAL_FLAG_AMBIGUOUS)) {
        if (result != NULL)
            *result = res;
        return SFM_E_SINGULAR;
    }
    double Ht[16];
    st = sfmi_selfcal_rectify(m, P, Q, K1, H0, n, X, Ht, &res);
    if (st < 0) {
        if (result != NULL && (res.flags & SFM_SELFCAL_FLAG_CHEIRALITY))
            *result = res;
        return st;
    }
    for (int i = 0; i < m; i++) {
        double cx = 0.5 * (wh[2 * i] - 1), cy = 0.5 * (wh[2 * i + 1] - 1);
        const double k[9] = {res.focal[i], 0, cx, 0, res.focal[i], cy, 0, 0, 1};
        memcpy(&K[9 * i], k, sizeof k);
    }
    memcpy(H, Ht, 16 * sizeof(double));
    if (result != NULL)
        *result = res;
    return SFM_OK;
}
