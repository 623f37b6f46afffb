/* The Levenberg-Marquardt driver on problems with known answers: a curve
 * fit, a line fit whose covariance has a closed form, a rotation and a unit
 * vector on their manifolds, a robust fit through outliers, and the
 * argument contract. */
#include <string.h>

#include "core/lm.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "solvers/small_math.h"
#include "sfm_test.h"

#define NPTS 40

typedef struct fit_data {
    double x[NPTS], y[NPTS];
    int n;
} fit_data;

/* The default options without the relative cost test, so a solve runs on
 * until the step or gradient test ends it. */
static sfmi_lm_options options_no_ftol(void)
{
    sfmi_lm_options o;
    sfmi_lm_default_options(&o);
    o.function_tolerance = 0.0;
    return o;
}

/* y = a exp(b x): r = a exp(b x) - y, J = (exp(b x), a x exp(b x)). */
static int exp_residual(const void *user, const double *const *v, int i, double *r, double *J)
{
    const fit_data *d = user;
    const double a = v[0][0], b = v[0][1];
    const double e = exp(b * d->x[i]);
    r[0] = a * e - d->y[i];
    if (J) {
        J[0] = e;
        J[1] = a * d->x[i] * e;
    }
    return 1;
}

/* y = c0 + c1 x, the two coefficients in two blocks. */
static int line_residual(const void *user, const double *const *v, int i, double *r, double *J)
{
    const fit_data *d = user;
    r[0] = v[0][0] + v[1][0] * d->x[i] - d->y[i];
    if (J) {
        J[0] = 1.0;
        J[1] = d->x[i];
    }
    return 1;
}

static size_t ws_doubles_ok(int nv, int nt, int rs)
{
    return sizeof(double) * (size_t)SFMI_LM_DENSE_WS_DOUBLES(nv, nt, rs) >=
           sfmi_lm_dense_workspace_size(nv, nt, rs);
}

SFM_TEST(lm_dense_recovers_an_exponential_from_a_far_start)
{
    fit_data d;
    d.n = 30;
    for (int i = 0; i < d.n; i++) {
        d.x[i] = -1.0 + 2.0 * i / (d.n - 1);
        d.y[i] = 2.5 * exp(-1.3 * d.x[i]);
    }
    double ab[2] = {1.0, 0.0};
    sfmi_lm_block blk = {ab, 2, SFMI_LM_EUCLIDEAN, 0, NULL, NULL};
    sfmi_lm_problem p = {&blk, 1, d.n, 1, exp_residual, &d, SFMI_LM_LOSS_SQUARED, 0.0, NULL};
    sfmi_lm_options o = options_no_ftol();
    o.step_tolerance = 1e-14;
    o.max_iterations = 100;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(2, 2, 1)];
    sfmi_lm_summary s;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_OK);
    SFM_CHECK_NEAR(ab[0], 2.5, 1e-9);
    SFM_CHECK_NEAR(ab[1], -1.3, 1e-9);
    SFM_CHECK(s.final_cost < 1e-18);
    SFM_CHECK(s.initial_cost > 1.0);
    SFM_CHECK(s.stop == SFMI_LM_STOP_GRADIENT || s.stop == SFMI_LM_STOP_STEP);
    SFM_CHECK(s.successful_steps >= 1 && s.iterations <= 100);
    SFM_CHECK(ws_doubles_ok(2, 2, 1));
}

SFM_TEST(lm_dense_line_fit_covariance_is_the_inverse_normal_matrix)
{
    /* For a linear model the solution is the least-squares one and the
     * covariance (J^T J)^-1 has the closed 2x2 form below. */
    fit_data d;
    d.n = NPTS;
    double Sx = 0, Sxx = 0, Sy = 0, Sxy = 0;
    for (int i = 0; i < d.n; i++) {
        d.x[i] = sfm_test_uniform(t, -3.0, 5.0);
        d.y[i] = 0.7 - 1.9 * d.x[i] + sfm_test_normal(t, 0.1);
        Sx += d.x[i];
        Sxx += d.x[i] * d.x[i];
        Sy += d.y[i];
        Sxy += d.x[i] * d.y[i];
    }
    const double det = d.n * Sxx - Sx * Sx;
    const double c1 = (d.n * Sxy - Sx * Sy) / det, c0 = (Sy - c1 * Sx) / d.n;
    double b0 = 0.0, b1 = 0.0;
    sfmi_lm_block blk[2] = {{&b0, 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL},
                            {&b1, 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL}};
    sfmi_lm_problem p = {blk, 2, d.n, 1, line_residual, &d, SFMI_LM_LOSS_SQUARED, 0.0, NULL};
    sfmi_lm_options o;
    sfmi_lm_default_options(&o);
    o.want_covariance = 1;
    o.function_tolerance = 0.0;
    o.step_tolerance = 1e-14;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(2, 2, 1)], cov[4];
    sfmi_lm_summary s;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, cov), SFM_OK);
    SFM_CHECK_NEAR(b0, c0, 1e-9);
    SFM_CHECK_NEAR(b1, c1, 1e-9);
    SFM_CHECK_EQ_INT(s.covariance_status, SFM_OK);
    SFM_CHECK_NEAR(cov[0], Sxx / det, 1e-12);
    SFM_CHECK_NEAR(cov[1], -Sx / det, 1e-12);
    SFM_CHECK_NEAR(cov[2], -Sx / det, 1e-12);
    SFM_CHECK_NEAR(cov[3], d.n / det, 1e-12);

    /* a constant block has no covariance rows: b1 held at its value */
    b0 = 0.0;
    b1 = -1.9;
    blk[1].manifold = SFMI_LM_CONSTANT;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, cov), SFM_OK);
    SFM_CHECK_NEAR(b1, -1.9, 0.0);
    SFM_CHECK_NEAR(b0, (Sy + 1.9 * Sx) / d.n, 1e-9);
    SFM_CHECK_NEAR(cov[0], 1.0 / d.n, 1e-12);
}

typedef struct rot_data {
    double a[3 * NPTS], b[3 * NPTS];
    int n;
} rot_data;

/* r = R a - b; d(exp([w]x) R a)/dw at 0 = -[R a]x. */
static int rot_residual(const void *user, const double *const *v, int i, double *r, double *J)
{
    const rot_data *d = user;
    double Ra[3];
    sfmi_matvec3(v[0], d->a + 3 * i, Ra);
    for (int k = 0; k < 3; k++)
        r[k] = Ra[k] - d->b[3 * i + k];
    if (J) {
        double K[9];
        sfm_skew(Ra, K);
        for (int k = 0; k < 9; k++)
            J[k] = -K[k];
    }
    return 1;
}

SFM_TEST(lm_dense_so3_block_finds_the_rotation)
{
    rot_data d;
    d.n = 10;
    double Rt[9], R[9];
    sfm_test_random_rotation(t, Rt);
    for (int i = 0; i < d.n; i++) {
        sfm_test_random_unit(t, d.a + 3 * i);
        sfmi_matvec3(Rt, d.a + 3 * i, d.b + 3 * i);
    }
    /* start 0.5 rad away */
    double w[3] = {0.3, -0.2, 0.35}, dR[9];
    sfm_rot_from_axis_angle(w, dR);
    sfmi_matmul3(dR, Rt, R);
    sfmi_lm_block blk = {R, 9, SFMI_LM_SO3, 0, NULL, NULL};
    sfmi_lm_problem p = {&blk, 1, d.n, 3, rot_residual, &d, SFMI_LM_LOSS_SQUARED, 0.0, NULL};
    sfmi_lm_options o = options_no_ftol();
    double ws[SFMI_LM_DENSE_WS_DOUBLES(9, 3, 3)];
    sfmi_lm_summary s;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_OK);
    for (int k = 0; k < 9; k++)
        SFM_CHECK_NEAR(R[k], Rt[k], 1e-9);
    /* still a rotation */
    double RRt[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            RRt[3 * r + c] = R[3 * r] * R[3 * c] + R[3 * r + 1] * R[3 * c + 1] + R[3 * r + 2] * R[3 * c + 2];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            SFM_CHECK_NEAR(RRt[3 * r + c], r == c ? 1.0 : 0.0, 1e-12);
}

typedef struct null_data {
    double A[4 * NPTS];
    int n;
} null_data;

/* r = a_i . u on the unit sphere of R^4: the minimiser is the smallest
 * right singular vector of A; J = a_i^T B. */
static int null_residual(const void *user, const double *const *v, int i, double *r, double *J)
{
    const null_data *d = user;
    const double *a = d->A + 4 * i;
    r[0] = a[0] * v[0][0] + a[1] * v[0][1] + a[2] * v[0][2] + a[3] * v[0][3];
    if (J) {
        double B[12];
        sfmi_lm_sphere_basis(v[0], 4, B);
        for (int c = 0; c < 3; c++)
            J[c] = a[0] * B[c] + a[1] * B[3 + c] + a[2] * B[6 + c] + a[3] * B[9 + c];
    }
    return 1;
}

SFM_TEST(lm_dense_sphere_block_finds_the_null_vector)
{
    /* rows orthogonal to a known unit u plus a small component along it */
    null_data d;
    d.n = 12;
    double u[4] = {0.2, -0.5, 0.7, 0.3}, nu = 0.0;
    for (int k = 0; k < 4; k++)
        nu += u[k] * u[k];
    for (int k = 0; k < 4; k++)
        u[k] /= sqrt(nu);
    for (int i = 0; i < d.n; i++) {
        double a[4], au = 0.0;
        for (int k = 0; k < 4; k++)
            a[k] = sfm_test_normal(t, 1.0);
        for (int k = 0; k < 4; k++)
            au += a[k] * u[k];
        for (int k = 0; k < 4; k++)
            d.A[4 * i + k] = a[k] - au * u[k];
    }
    double x[4] = {0.5, -0.5, 0.5, 0.5};
    sfmi_lm_block blk = {x, 4, SFMI_LM_SPHERE, 0, NULL, NULL};
    sfmi_lm_problem p = {&blk, 1, d.n, 1, null_residual, &d, SFMI_LM_LOSS_SQUARED, 0.0, NULL};
    sfmi_lm_options o = options_no_ftol();
    double ws[SFMI_LM_DENSE_WS_DOUBLES(4, 3, 1)];
    sfmi_lm_summary s;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_OK);
    double dot = 0.0, nx = 0.0;
    for (int k = 0; k < 4; k++) {
        dot += x[k] * u[k];
        nx += x[k] * x[k];
    }
    SFM_CHECK_NEAR(fabs(dot), 1.0, 1e-10);
    SFM_CHECK_NEAR(nx, 1.0, 1e-14);
    /* the basis is orthonormal and orthogonal to x */
    double B[12];
    sfmi_lm_sphere_basis(x, 4, B);
    for (int a = 0; a < 3; a++) {
        double bx = 0.0;
        for (int r = 0; r < 4; r++)
            bx += B[r * 3 + a] * x[r];
        SFM_CHECK_NEAR(bx, 0.0, 1e-14);
        for (int b = 0; b < 3; b++) {
            double bb = 0.0;
            for (int r = 0; r < 4; r++)
                bb += B[r * 3 + a] * B[r * 3 + b];
            SFM_CHECK_NEAR(bb, a == b ? 1.0 : 0.0, 1e-14);
        }
    }
}

SFM_TEST(lm_dense_cauchy_loss_ignores_gross_outliers)
{
    fit_data d;
    d.n = NPTS;
    for (int i = 0; i < d.n; i++) {
        d.x[i] = sfm_test_uniform(t, -2.0, 2.0);
        d.y[i] = 1.0 + 0.5 * d.x[i] + sfm_test_normal(t, 0.01);
        if (i % 5 == 0)
            d.y[i] += sfm_test_uniform(t, 5.0, 20.0);
    }
    double b0 = 0.0, b1 = 0.0;
    sfmi_lm_block blk[2] = {{&b0, 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL},
                            {&b1, 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL}};
    sfmi_lm_problem p = {blk, 2, d.n, 1, line_residual, &d, SFMI_LM_LOSS_CAUCHY, 0.05, NULL};
    sfmi_lm_options o;
    sfmi_lm_default_options(&o);
    o.max_iterations = 200;
    o.function_tolerance = 1e-12;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(2, 2, 1)];
    sfmi_lm_summary s;
    /* from the least-squares start (pulled up by the outliers) */
    b0 = 3.0;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_OK);
    SFM_CHECK_NEAR(b0, 1.0, 0.02);
    SFM_CHECK_NEAR(b1, 0.5, 0.02);
}

/* The Cauchy cost, 1/2 sum a^2 log(1 + r^2/a^2), against an independent
 * sum of log1p in long double: small residuals, residuals whose factors
 * push the running product past 2^256 (the engine takes powers out) and
 * one whose factor alone is above 2^256. */
SFM_TEST(lm_dense_cauchy_cost_matches_sum_of_log1p)
{
    fit_data d;
    d.n = NPTS;
    const double a = 0.05, a2 = a * a;
    for (int i = 0; i < d.n; i++) {
        d.x[i] = i;
        if (i < 25)
            d.y[i] = 0.01 * (double)(i + 1); /* factors 1.04 .. 26 */
        else if (i < 39)
            d.y[i] = 1e15 * (double)(i - 24); /* about 2^108 each */
        else
            d.y[i] = 1e80; /* about 2^540 */
    }
    double b0 = 0.0, b1 = 0.0;
    sfmi_lm_block blk[2] = {{&b0, 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL},
                            {&b1, 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL}};
    sfmi_lm_problem p = {blk, 2, d.n, 1, line_residual, &d, SFMI_LM_LOSS_CAUCHY, a, NULL};
    sfmi_lm_options o;
    sfmi_lm_default_options(&o);
    o.max_iterations = 0;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(2, 2, 1)];
    sfmi_lm_summary s;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_OK);
    long double ref = 0.0L;
    for (int i = 0; i < d.n; i++) {
        long double r = (long double)d.y[i];
        ref += (long double)a2 * log1pl(r * r / (long double)a2);
    }
    ref *= 0.5L;
    SFM_CHECK(fabsl((long double)s.initial_cost - ref) <= 1e-13L * ref);
}

SFM_TEST(lm_dense_contract_statuses_and_nothing_written)
{
    fit_data d;
    d.n = 5;
    for (int i = 0; i < d.n; i++) {
        d.x[i] = i;
        d.y[i] = 2.0 * i;
    }
    double b[2] = {0.0, 0.0};
    sfmi_lm_block blk[2] = {{&b[0], 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL},
                            {&b[1], 1, SFMI_LM_EUCLIDEAN, 0, NULL, NULL}};
    sfmi_lm_problem p = {blk, 2, d.n, 1, line_residual, &d, SFMI_LM_LOSS_SQUARED, 0.0, NULL};
    sfmi_lm_options o;
    sfmi_lm_default_options(&o);
    double ws[SFMI_LM_DENSE_WS_DOUBLES(2, 2, 1)];
    sfmi_lm_summary s;
    size_t need = sfmi_lm_dense_workspace_size(2, 2, 1);
    SFM_CHECK(need > 0 && need <= sizeof ws);
    sfm_test_fill_canary(&s, sizeof s);
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(NULL, &o, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, NULL, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, need - 1, &s, NULL), SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, NULL, need, &s, NULL), SFM_E_WORKSPACE);
    o.want_covariance = 1;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    o.want_covariance = 0;
    o.max_iterations = -1;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    sfmi_lm_default_options(&o);
    o.initial_radius = (double)NAN;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    sfmi_lm_default_options(&o);
    p.loss = SFMI_LM_LOSS_HUBER;
    p.loss_scale = (double)NAN;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_NONFINITE);
    p.loss_scale = -1.0;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    p.loss = SFMI_LM_LOSS_SQUARED;
    blk[1].manifold = SFMI_LM_SO3; /* size 1 cannot be a rotation */
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    blk[1].manifold = SFMI_LM_CUSTOM; /* no plus() */
    blk[1].tangent = 1;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_ARGUMENT);
    blk[1].manifold = SFMI_LM_EUCLIDEAN;
    b[1] = (double)NAN;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(&s, sizeof s));
    SFM_CHECK(b[0] == 0.0);
    /* zero iterations: the cost only, values unchanged */
    b[1] = 0.0;
    o.max_iterations = 0;
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_OK);
    SFM_CHECK_EQ_INT(s.stop, SFMI_LM_STOP_MAX_ITERATIONS);
    SFM_CHECK_NEAR(s.final_cost, 0.5 * (4 + 16 + 36 + 64), 1e-12);
    SFM_CHECK(b[0] == 0.0 && b[1] == 0.0);
    /* every block constant: nothing to refine */
    blk[0].manifold = blk[1].manifold = SFMI_LM_CONSTANT;
    sfmi_lm_default_options(&o);
    SFM_CHECK_EQ_INT(sfmi_lm_dense_solve(&p, &o, ws, sizeof ws, &s, NULL), SFM_OK);
    SFM_CHECK_EQ_INT(s.stop, SFMI_LM_STOP_NO_PARAMETERS);
}
