/*
 * Real nonsymmetric eigenproblem: Householder reduction to upper Hessenberg
 * form, then the Francis implicit double-shift QR iteration to real Schur form
 * T = Z^T A Z (Golub & Van Loan, Matrix Computations, 4th ed., 7.4-7.5;
 * exceptional shifts after 10 and 20 iterations without deflation as in
 * LAPACK's dlahqr), then eigenvectors of T by back substitution on its
 * quasi-triangular form and back-transformation by Z.
 *
 * Layout of results (as LAPACK's dgeev): complex pairs take two columns, the
 * real and imaginary parts of the eigenvector of the eigenvalue with positive
 * imaginary part; each vector has unit Euclidean norm and its component of
 * largest modulus real and positive.
 *
 * Order: descending real part, then descending imaginary part, conjugate
 * pairs kept adjacent (when a real eigenvalue has exactly the real part of a
 * pair, the pair comes first).
 *
 * The matrix is scaled by an exact power of two to bring its largest entry
 * into [0.5, 1) first; no balancing is done.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "core/dmath.h"

/* QR iterations allowed per eigenvalue on average before giving up. */
#define EIG_ITERS_PER_EIGENVALUE 40
/* A back-substituted eigenvector entry above this rescales the vector. */
#define EIG_BIG 1e100

typedef struct eig_ws {
    double *H;   /* n x n: Hessenberg, then Schur form T, then Z X */
    double *Z;   /* n x n: accumulated orthogonal transformations */
    double *X;   /* n x n: eigenvectors of T */
    double *wr;  /* n */
    double *wi;  /* n */
    double *v;   /* n: Householder vector */
    int *unit;   /* n: start index of each eigenvalue unit, sorted */
} eig_ws;

static void eig_layout(sfmi_arena *a, int n, eig_ws *w)
{
    w->H = SFM_ARENA_ARRAY(a, double, (size_t)n * n);
    w->Z = SFM_ARENA_ARRAY(a, double, (size_t)n * n);
    w->X = SFM_ARENA_ARRAY(a, double, (size_t)n * n);
    w->wr = SFM_ARENA_ARRAY(a, double, n);
    w->wi = SFM_ARENA_ARRAY(a, double, n);
    w->v = SFM_ARENA_ARRAY(a, double, n);
    w->unit = SFM_ARENA_ARRAY(a, int, n);
}

size_t sfm_eig_workspace_size(int n)
{
    if (!sfmi_la_dim_ok(n))
        return 0;
    sfmi_arena a;
    eig_ws w;
    sfmi_arena_measure(&a);
    eig_layout(&a, n, &w);
    return sfmi_arena_required(&a);
}

#define AT(M, i, j) (M)[(size_t)(i) * (size_t)n + (size_t)(j)]

/* Householder reduction to upper Hessenberg form, Z = P_0 P_1 ... */
static void hessenberg(double *H, double *Z, double *v, int n)
{
    for (int k = 0; k + 2 < n; k++) {
        double alpha = AT(H, k + 1, k);
        double scale = 0.0;
        for (int i = k + 2; i < n; i++)
            scale = fmax(scale, fabs(AT(H, i, k)));
        if (scale == 0.0)
            continue;
        double xn = 0.0;
        for (int i = k + 2; i < n; i++) {
            double t = AT(H, i, k) / scale;
            xn += t * t;
        }
        xn = scale * sqrt(xn);
        double beta = -copysign(sfmi_hypot(alpha, xn), alpha);
        double tau = (beta - alpha) / beta;
        double inv = 1.0 / (alpha - beta);
        v[k + 1] = 1.0;
        for (int i = k + 2; i < n; i++)
            v[i] = AT(H, i, k) * inv;
        AT(H, k + 1, k) = beta;
        for (int i = k + 2; i < n; i++)
            AT(H, i, k) = 0.0;
        /* H <- P H: columns k+1.. */
        for (int j = k + 1; j < n; j++) {
            double s = 0.0;
            for (int i = k + 1; i < n; i++)
                s += v[i] * AT(H, i, j);
            s *= tau;
            for (int i = k + 1; i < n; i++)
                AT(H, i, j) -= s * v[i];
        }
        /* H <- H P, Z <- Z P */
        for (int i = 0; i < n; i++) {
            double s = 0.0, sz = 0.0;
            for (int j = k + 1; j < n; j++) {
                s += AT(H, i, j) * v[j];
                sz += AT(Z, i, j) * v[j];
            }
            s *= tau;
            sz *= tau;
            for (int j = k + 1; j < n; j++) {
                AT(H, i, j) -= s * v[j];
                AT(Z, i, j) -= sz * v[j];
            }
        }
    }
}

/* Reflector I - tau u u^T, u = (1, u1, u2), mapping (x, y, z) to (beta, 0, 0).
 * tau = 0 when y = z = 0. Returns beta. */
static double house3(double x, double y, double z, double *u1, double *u2, double *tau)
{
    double sc = fabs(x) + fabs(y) + fabs(z);
    if (sc == 0.0 || (y == 0.0 && z == 0.0)) {
        *tau = 0.0;
        *u1 = *u2 = 0.0;
        return x;
    }
    x /= sc;
    y /= sc;
    z /= sc;
    double beta = -copysign(sqrt(x * x + y * y + z * z), x);
    *tau = (beta - x) / beta;
    double inv = 1.0 / (x - beta);
    *u1 = y * inv;
    *u2 = z * inv;
    return beta * sc;
}

/* The reflector applied to count 3-vectors (2-vectors when three == 0): the
 * j-th has its components at p[j step], p[j step + comp], p[j step + 2 comp]. */
static void reflect(double *p, size_t comp, size_t step, int count, int three, double u1,
                    double u2, double tau)
{
    for (int j = 0; j < count; j++, p += step) {
        double s = p[0] + u1 * p[comp] + (three ? u2 * p[2 * comp] : 0.0);
        s *= tau;
        p[0] -= s;
        p[comp] -= s * u1;
        if (three)
            p[2 * comp] -= s * u2;
    }
}

/* Apply the reflector (u = (1, u1, u2), or (1, u1) when three == 0) to rows
 * r..r+2 of H over columns c0..n-1, to columns r..r+2 of H over rows 0..r1,
 * and to columns r..r+2 of Z (when not NULL). */
static void apply_reflector(double *H, double *Z, int n, int r, int three, double u1, double u2,
                            double tau, int c0, int r1)
{
    if (tau == 0.0)
        return;
    reflect(&AT(H, r, c0), (size_t)n, 1, n - c0, three, u1, u2, tau);
    reflect(&AT(H, 0, r), 1, (size_t)n, r1 + 1, three, u1, u2, tau);
    if (Z != NULL)
        reflect(&AT(Z, 0, r), 1, (size_t)n, n, three, u1, u2, tau);
}

/* Francis double-shift QR on the Hessenberg H: on success H holds the real
 * Schur form T (2x2 diagonal blocks for complex pairs, the others upper
 * triangular), Z (when not NULL) has been multiplied by the transformations,
 * and wr/wi hold the eigenvalues in the order of T's diagonal, pairs with
 * positive imaginary part first. */
static int francis_qr(double *H, double *Z, double *wr, double *wi, int n)
{
    double norm = 0.0;
    for (size_t i = 0; i < (size_t)n * (size_t)n; i++)
        norm = fmax(norm, fabs(H[i]));
    const int max_total = EIG_ITERS_PER_EIGENVALUE * (n > 10 ? n : 10);
    int total = 0, iter = 0;
    int hi = n - 1;
    while (hi >= 0) {
        int l = hi;
        while (l > 0) {
            double s = fabs(AT(H, l - 1, l - 1)) + fabs(AT(H, l, l));
            if (s == 0.0)
                s = norm;
            if (fabs(AT(H, l, l - 1)) <= DBL_EPSILON * s) {
                AT(H, l, l - 1) = 0.0;
                break;
            }
            l--;
        }
        if (l == hi) {
            wr[hi] = AT(H, hi, hi);
            wi[hi] = 0.0;
            hi--;
            iter = 0;
            continue;
        }
        if (l == hi - 1) {
            const int p0 = hi - 1;
            double a = AT(H, p0, p0), b = AT(H, p0, hi), c = AT(H, hi, p0), d = AT(H, hi, hi);
            double p = 0.5 * (a - d), q = p * p + b * c;
            if (q >= 0.0) {
                /* real pair: rotate (zz, c), an eigenvector of the block for
                 * d + zz, onto e_1 to triangularize */
                double zz = p + copysign(sqrt(q), p);
                double r = sfmi_hypot(zz, c);
                double cs = zz / r, sn = c / r;
                /* (x, y) <- (cs x + sn y, -sn x + cs y) on rows p0, hi of H,
                 * then on columns p0, hi of H and Z */
                sfmi_la_rotate(&AT(H, p0, p0), &AT(H, hi, p0), n - p0, 1, cs, -sn);
                sfmi_la_rotate(&AT(H, 0, p0), &AT(H, 0, hi), hi + 1, (size_t)n, cs, -sn);
                if (Z != NULL)
                    sfmi_la_rotate(&AT(Z, 0, p0), &AT(Z, 0, hi), n, (size_t)n, cs, -sn);
                AT(H, hi, p0) = 0.0;
                wr[p0] = AT(H, p0, p0);
                wr[hi] = AT(H, hi, hi);
                wi[p0] = wi[hi] = 0.0;
            } else {
                double im = sqrt(-q);
                wr[p0] = wr[hi] = d + p;
                wi[p0] = im;
                wi[hi] = -im;
            }
            hi -= 2;
            iter = 0;
            continue;
        }
        if (total >= max_total)
            return SFM_E_NO_CONVERGENCE;
        total++;
        iter++;
        double tr, det;
        if (iter % 10 == 0) {
            double s = fabs(AT(H, hi, hi - 1)) + fabs(AT(H, hi - 1, hi - 2));
            double h11 = 0.75 * s + AT(H, hi, hi), h12 = -0.4375 * s, h21 = s;
            tr = 2.0 * h11;
            det = h11 * h11 - h12 * h21;
        } else {
            tr = AT(H, hi - 1, hi - 1) + AT(H, hi, hi);
            det = AT(H, hi - 1, hi - 1) * AT(H, hi, hi) - AT(H, hi - 1, hi) * AT(H, hi, hi - 1);
        }
        /* first column of (H - s1 I)(H - s2 I) on the active block */
        double h00 = AT(H, l, l), h01 = AT(H, l, l + 1), h10 = AT(H, l + 1, l);
        double h11 = AT(H, l + 1, l + 1), h21 = AT(H, l + 2, l + 1);
        double x = h00 * h00 + h01 * h10 - tr * h00 + det;
        double y = h10 * (h00 + h11 - tr);
        double z = h10 * h21;
        for (int k = l; k <= hi - 2; k++) {
            double u1, u2, tau;
            double beta = house3(x, y, z, &u1, &u2, &tau);
            if (k > l) {
                AT(H, k, k - 1) = beta;
                AT(H, k + 1, k - 1) = 0.0;
                AT(H, k + 2, k - 1) = 0.0;
            }
            int r1 = k + 3 < hi ? k + 3 : hi;
            apply_reflector(H, Z, n, k, 1, u1, u2, tau, k, r1);
            x = AT(H, k + 1, k);
            y = AT(H, k + 2, k);
            if (k < hi - 2)
                z = AT(H, k + 3, k);
        }
        {
            const int k = hi - 1;
            double u1, u2, tau;
            double beta = house3(x, y, 0.0, &u1, &u2, &tau);
            AT(H, k, k - 1) = beta;
            AT(H, k + 1, k - 1) = 0.0;
            apply_reflector(H, Z, n, k, 0, u1, 0.0, tau, k, hi);
        }
    }
    return SFM_OK;
}

/* (ar + i ai) / (br + i bi), Smith's algorithm. */
static void cdiv(double ar, double ai, double br, double bi, double *cr, double *ci)
{
    if (fabs(br) >= fabs(bi)) {
        double r = bi / br, d = br + r * bi;
        *cr = (ar + ai * r) / d;
        *ci = (ai - ar * r) / d;
    } else {
        double r = br / bi, d = bi + r * br;
        *cr = (ar * r + ai) / d;
        *ci = (ai * r - ar) / d;
    }
}

/* Solve the complex 2x2 system M x = r (M = Mr + i Mi, row-major) by Gaussian
 * elimination with complete pivoting, pivots below smin raised to smin (as
 * LAPACK's dlaln2): backward stable even when M is nearly singular, where
 * Cramer's rule is not. */
static void solve2(const double Mr[4], const double Mi[4], const double rr[2], const double ri[2],
                   double smin, double xr[2], double xi[2])
{
    /* pivot: the entry of largest |re| + |im| */
    int p = 0;
    double best = -1.0;
    for (int q = 0; q < 4; q++) {
        double v = fabs(Mr[q]) + fabs(Mi[q]);
        if (v > best) {
            best = v;
            p = q;
        }
    }
    const int pr = p >> 1, pc = p & 1; /* pivot row and column */
    const int orr = 1 - pr, oc = 1 - pc;
    double m00r = Mr[pr * 2 + pc], m00i = Mi[pr * 2 + pc];
    double m01r = Mr[pr * 2 + oc], m01i = Mi[pr * 2 + oc];
    double m10r = Mr[orr * 2 + pc], m10i = Mi[orr * 2 + pc];
    double m11r = Mr[orr * 2 + oc], m11i = Mi[orr * 2 + oc];
    double r0r = rr[pr], r0i = ri[pr], r1r = rr[orr], r1i = ri[orr];
    if (best < smin) {
        m00r = smin;
        m00i = 0.0;
    }
    double lr, li;
    cdiv(m10r, m10i, m00r, m00i, &lr, &li);
    double u11r = m11r - (lr * m01r - li * m01i);
    double u11i = m11i - (lr * m01i + li * m01r);
    if (fabs(u11r) + fabs(u11i) < smin) {
        u11r = smin;
        u11i = 0.0;
    }
    double y1r = r1r - (lr * r0r - li * r0i);
    double y1i = r1i - (lr * r0i + li * r0r);
    double x1r, x1i, x0r, x0i;
    cdiv(y1r, y1i, u11r, u11i, &x1r, &x1i);
    cdiv(r0r - (m01r * x1r - m01i * x1i), r0i - (m01r * x1i + m01i * x1r), m00r, m00i, &x0r,
         &x0i);
    xr[pc] = x0r;
    xi[pc] = x0i;
    xr[oc] = x1r;
    xi[oc] = x1i;
}

static void scale_col(double *X, int n, int col, int upto, double s)
{
    for (int i = 0; i <= upto; i++)
        AT(X, i, col) *= s;
}

/* Eigenvectors of the quasi-triangular T into X (columns, LAPACK layout). */
static void schur_vectors(const double *T, const double *wr, const double *wi, double *X, int n)
{
    double norm = 0.0;
    for (size_t i = 0; i < (size_t)n * (size_t)n; i++)
        norm = fmax(norm, fabs(T[i]));
    const double small = DBL_EPSILON * (norm > 0.0 ? norm : 1.0);
    memset(X, 0, sizeof(double) * (size_t)n * (size_t)n);
    for (int k = n - 1; k >= 0; k--) {
        if (wi[k] == 0.0) {
            const double lam = wr[k];
            AT(X, k, k) = 1.0;
            int i = k - 1;
            while (i >= 0) {
                if (i > 0 && wi[i] < 0.0) {
                    /* 2x2 block (i-1, i) of a complex pair */
                    double r1 = 0.0, r2 = 0.0;
                    for (int j = i + 1; j <= k; j++) {
                        r1 += AT(T, i - 1, j) * AT(X, j, k);
                        r2 += AT(T, i, j) * AT(X, j, k);
                    }
                    const double Mr[4] = {AT(T, i - 1, i - 1) - lam, AT(T, i - 1, i),
                                          AT(T, i, i - 1), AT(T, i, i) - lam};
                    const double Mi[4] = {0.0, 0.0, 0.0, 0.0};
                    const double rr[2] = {-r1, -r2}, ri[2] = {0.0, 0.0};
                    double xr[2], xi[2];
                    solve2(Mr, Mi, rr, ri, small, xr, xi);
                    double x1 = xr[0], x2 = xr[1];
                    AT(X, i - 1, k) = x1;
                    AT(X, i, k) = x2;
                    double big = fmax(fabs(x1), fabs(x2));
                    if (big > EIG_BIG)
                        scale_col(X, n, k, k, 1.0 / big);
                    i -= 2;
                } else {
                    double r = 0.0;
                    for (int j = i + 1; j <= k; j++)
                        r += AT(T, i, j) * AT(X, j, k);
                    double den = AT(T, i, i) - lam;
                    if (fabs(den) < small)
                        den = small;
                    double xi = -r / den;
                    AT(X, i, k) = xi;
                    if (fabs(xi) > EIG_BIG)
                        scale_col(X, n, k, k, 1.0 / fabs(xi));
                    i -= 1;
                }
            }
        } else if (wi[k] < 0.0) {
            /* pair (k-1, k): eigenvalue lr + i li with li > 0; real part in
             * column k-1, imaginary part in column k */
            const int p = k - 1;
            const double lr = wr[p], li = wi[p];
            double a = AT(T, p, p), b = AT(T, p, k), c = AT(T, k, p), d = AT(T, k, k);
            if (fabs(b) >= fabs(c)) {
                AT(X, p, p) = b;
                AT(X, p, k) = 0.0;
                AT(X, k, p) = lr - a;
                AT(X, k, k) = li;
            } else {
                AT(X, p, p) = lr - d;
                AT(X, p, k) = li;
                AT(X, k, p) = c;
                AT(X, k, k) = 0.0;
            }
            int i = p - 1;
            while (i >= 0) {
                if (i > 0 && wi[i] < 0.0) {
                    double r1r = 0.0, r1i = 0.0, r2r = 0.0, r2i = 0.0;
                    for (int j = i + 1; j <= k; j++) {
                        r1r += AT(T, i - 1, j) * AT(X, j, p);
                        r1i += AT(T, i - 1, j) * AT(X, j, k);
                        r2r += AT(T, i, j) * AT(X, j, p);
                        r2i += AT(T, i, j) * AT(X, j, k);
                    }
                    const double Mr[4] = {AT(T, i - 1, i - 1) - lr, AT(T, i - 1, i),
                                          AT(T, i, i - 1), AT(T, i, i) - lr};
                    const double Mi[4] = {-li, 0.0, 0.0, -li};
                    const double rr[2] = {-r1r, -r2r}, ri[2] = {-r1i, -r2i};
                    double xr[2], xi[2];
                    solve2(Mr, Mi, rr, ri, small, xr, xi);
                    double x1r = xr[0], x1i = xi[0], x2r = xr[1], x2i = xi[1];
                    AT(X, i - 1, p) = x1r;
                    AT(X, i - 1, k) = x1i;
                    AT(X, i, p) = x2r;
                    AT(X, i, k) = x2i;
                    double big = fmax(fmax(fabs(x1r), fabs(x1i)), fmax(fabs(x2r), fabs(x2i)));
                    if (big > EIG_BIG) {
                        scale_col(X, n, p, k, 1.0 / big);
                        scale_col(X, n, k, k, 1.0 / big);
                    }
                    i -= 2;
                } else {
                    double rr = 0.0, ri = 0.0;
                    for (int j = i + 1; j <= k; j++) {
                        rr += AT(T, i, j) * AT(X, j, p);
                        ri += AT(T, i, j) * AT(X, j, k);
                    }
                    double xr, xi;
                    double dr = AT(T, i, i) - lr, di = -li;
                    if (fabs(dr) + fabs(di) < small) {
                        dr = small;
                        di = 0.0;
                    }
                    cdiv(-rr, -ri, dr, di, &xr, &xi);
                    AT(X, i, p) = xr;
                    AT(X, i, k) = xi;
                    double big = fmax(fabs(xr), fabs(xi));
                    if (big > EIG_BIG) {
                        scale_col(X, n, p, k, 1.0 / big);
                        scale_col(X, n, k, k, 1.0 / big);
                    }
                    i -= 1;
                }
            }
            k--; /* the pair's first index is done too */
        }
    }
}

/* Unit norm, component of largest modulus real and positive. */
static void normalize_vectors(double *V, const double *wi, int n)
{
    for (int k = 0; k < n; k++) {
        if (wi[k] == 0.0) {
            double s = 0.0, big = 0.0;
            int ib = 0;
            for (int i = 0; i < n; i++) {
                double v = AT(V, i, k);
                s += v * v;
                if (fabs(v) > big) {
                    big = fabs(v);
                    ib = i;
                }
            }
            if (s > 0.0) {
                double inv = copysign(1.0 / sqrt(s), AT(V, ib, k));
                for (int i = 0; i < n; i++)
                    AT(V, i, k) *= inv;
            }
        } else if (wi[k] > 0.0 && k + 1 < n) {
            double s = 0.0, big = 0.0;
            int ib = 0;
            for (int i = 0; i < n; i++) {
                double re = AT(V, i, k), im = AT(V, i, k + 1);
                double m2 = re * re + im * im;
                s += m2;
                if (m2 > big) {
                    big = m2;
                    ib = i;
                }
            }
            if (s > 0.0) {
                /* multiply by conj(x_ib) / (|x_ib| |x|) */
                double mod = sqrt(big), nrm = sqrt(s);
                double cr = AT(V, ib, k) / mod / nrm, ci = -AT(V, ib, k + 1) / mod / nrm;
                /* Both parts written as sums (with -ci precomputed): GCC 12's
                 * vectorizer turns the pair (a*b - c*d, a*e + c*f) into a fused
                 * multiply-add-subtract under -march=native even with
                 * -ffp-contract=off, which would change the rounding on
                 * FMA-capable x86-64 only. mk/check-fma.mk checks the object. */
                const double nci = -ci;
                for (int i = 0; i < n; i++) {
                    double re = AT(V, i, k), im = AT(V, i, k + 1);
                    AT(V, i, k) = re * cr + im * nci;
                    AT(V, i, k + 1) = re * ci + im * cr;
                }
                AT(V, ib, k + 1) = 0.0;
            }
            k++;
        }
    }
}

int sfm_eig(const double *A, int n, double *wr_out, double *wi_out, double *V, void *ws,
            size_t ws_size)
{
    if (A == NULL || wr_out == NULL || wi_out == NULL || ws == NULL || !sfmi_la_dim_ok(n))
        return SFM_E_ARGUMENT;
    const size_t nn = (size_t)n * (size_t)n;
    if (!sfmi_la_all_finite(A, nn))
        return SFM_E_NONFINITE;
    sfmi_arena ar;
    eig_ws w;
    if (ws_size < sfm_eig_workspace_size(n))
        return SFM_E_WORKSPACE;
    sfmi_arena_init(&ar, ws, ws_size);
    eig_layout(&ar, n, &w);
    if (!sfmi_arena_ok(&ar))
        return SFM_E_WORKSPACE;

    const double f = sfmi_la_pow2_scale(sfmi_la_max_abs(A, nn));
    for (size_t i = 0; i < nn; i++)
        w.H[i] = A[i] * f;
    double *Z = V != NULL ? w.Z : NULL;
    if (Z != NULL) {
        memset(Z, 0, sizeof(double) * nn);
        for (int i = 0; i < n; i++)
            AT(Z, i, i) = 1.0;
    }
    hessenberg(w.H, w.Z, w.v, n);
    int st = francis_qr(w.H, Z, w.wr, w.wi, n);
    if (st != SFM_OK)
        return st;
    if (Z != NULL) {
        schur_vectors(w.H, w.wr, w.wi, w.X, n);
        /* H <- Z X (X is upper quasi-triangular) */
        for (int i = 0; i < n; i++)
            for (int k = 0; k < n; k++) {
                int top = (w.wi[k] > 0.0 && k + 1 < n) ? k + 1 : k;
                double s = 0.0;
                for (int j = 0; j <= top; j++)
                    s += AT(Z, i, j) * AT(w.X, j, k);
                AT(w.H, i, k) = s;
            }
        normalize_vectors(w.H, w.wi, n);
    }
    /* sort units (a real eigenvalue or a pair) by descending real part, then
     * descending imaginary part of the unit's first entry */
    int nu = 0;
    for (int k = 0; k < n; k++) {
        int p = nu;
        while (p > 0) {
            int q = w.unit[p - 1];
            if (w.wr[q] > w.wr[k] || (w.wr[q] == w.wr[k] && w.wi[q] >= w.wi[k]))
                break;
            w.unit[p] = q;
            p--;
        }
        w.unit[p] = k;
        nu++;
        if (w.wi[k] > 0.0)
            k++;
    }
    const double finv = 1.0 / f;
    int col = 0;
    for (int u = 0; u < nu; u++) {
        int k = w.unit[u];
        int sz = w.wi[k] > 0.0 ? 2 : 1;
        for (int c = 0; c < sz; c++, col++) {
            wr_out[col] = w.wr[k + c] * finv;
            wi_out[col] = w.wi[k + c] * finv;
            if (V != NULL)
                for (int i = 0; i < n; i++)
                    V[(size_t)i * n + col] = AT(w.H, i, k + c);
        }
    }
    return SFM_OK;
}
