/*
 * Generated action-matrix solvers against known answers: System 10 of Zhou &
 * Roumeliotis (three equations u_k^T C v_k = c_k built from a true rotation)
 * must return the true Cayley vector among its solutions.
 */
#include <math.h>

#include "sfm_test.h"
#include "sfm/sfm_pose.h"
#include "solvers/generated/r2r_tmpl.h"

SFM_TEST(r2r_tmpl_sys10_truth_among_solutions)
{
    int found = 0, trials = 50;
    for (int it = 0; it < trials; it++) {
        double s[3], in[21], sol[8 * 3];
        for (int i = 0; i < 3; i++)
            s[i] = 2.0 * sfm_rng_uniform(&t->rng) - 1.0;
        double ss = s[0] * s[0] + s[1] * s[1] + s[2] * s[2], C[9];
        double S[9] = {0, -s[2], s[1], s[2], 0, -s[0], -s[1], s[0], 0};
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                C[3 * r + c] = ((r == c ? 1.0 - ss : 0.0) + 2.0 * S[3 * r + c] + 2.0 * s[r] * s[c]) / (1.0 + ss);
        for (int k = 0; k < 3; k++) {
            double *u = in + 7 * k, *v = u + 3, cv[3];
            for (int i = 0; i < 6; i++)
                u[i] = 2.0 * sfm_rng_uniform(&t->rng) - 1.0;
            for (int r = 0; r < 3; r++)
                cv[r] = C[3 * r] * v[0] + C[3 * r + 1] * v[1] + C[3 * r + 2] * v[2];
            u[6] = u[0] * cv[0] + u[1] * cv[1] + u[2] * cv[2];
        }
        static double ws[SFMI_TMPL_SYS10_WS];
        int n = sfmi_tmpl_sys10(in, sol, ws);
        SFM_CHECK(n >= 1 && n <= SFMI_TMPL_SYS10_NSOL);
        for (int j = 0; j < n; j++) {
            double e = fabs(sol[3 * j] - s[0]) + fabs(sol[3 * j + 1] - s[1]) + fabs(sol[3 * j + 2] - s[2]);
            if (e < 1e-6) {
                found++;
                break;
            }
        }
    }
    SFM_CHECK_MSG(found == trials, "truth found in %d of %d", found, trials);
}

/* Pose x2 = R x1 + t up to the scale of t: all three points in front of
 * both cameras for t or for -t (midpoint depths of each bearing pair). */
static int upright_in_front(const double *x1, const double *x2, const double R[9], const double t[3])
{
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        int ok = 1;
        for (int i = 0; i < 3; i++) {
            double a[3], b[3], c[3];
            for (int r = 0; r < 3; r++) {
                a[r] = R[3 * r] * x1[3 * i] + R[3 * r + 1] * x1[3 * i + 1] + R[3 * r + 2] * x1[3 * i + 2];
                b[r] = x2[3 * i + r];
                c[r] = sgn * t[r];
            }
            /* l1 a - l2 b = -c in least squares */
            double aa = a[0] * a[0] + a[1] * a[1] + a[2] * a[2], bb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
            double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            double ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2], bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
            double det = aa * bb - ab * ab;
            double l1 = (-ac * bb + ab * bc) / det, l2 = (aa * bc - ab * ac) / det;
            ok &= l1 > 0.0 && l2 > 0.0;
        }
        if (ok)
            return 1;
    }
    return 0;
}

/* The generated upright 3-point template against the closed-form
 * sfm_relpose_upright_3pt on the same random upright instances (gravity
 * along y in both cameras): every closed-form pose is among the template's
 * real solutions, and every template solution that puts the points in front
 * of both cameras is among the closed-form poses (which keeps only those).
 * Agreement to 1e-5: near-meeting roots cost the template about 1e-6. */
SFM_TEST(r2r_tmpl_upright3pt_matches_closed_form)
{
    int trials = SFM_TEST_ITERS(2000), same = 0, truth = 0;
    for (int it = 0; it < trials; it++) {
        /* points in front of both cameras need the cameras to face alike */
        double th = sfm_test_uniform(t, -1.5, 1.5), c = cos(th), s = sin(th);
        double R[9] = {c, 0, s, 0, 1, 0, -s, 0, c}, tv[3], x1[9], x2[9];
        sfm_test_random_unit(t, tv);
        for (int i = 0; i < 3; i++) {
            double X[3], Y[3];
            do {
                X[0] = sfm_test_uniform(t, -1.5, 1.5);
                X[1] = sfm_test_uniform(t, -1.5, 1.5);
                X[2] = sfm_test_uniform(t, 2.0, 6.0);
                for (int r = 0; r < 3; r++)
                    Y[r] = R[3 * r] * X[0] + R[3 * r + 1] * X[1] + R[3 * r + 2] * X[2] + tv[r];
            } while (Y[2] < 0.5);
            double nx = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
            double ny = sqrt(Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]);
            for (int r = 0; r < 3; r++) {
                x1[3 * i + r] = X[r] / nx;
                x2[3 * i + r] = Y[r] / ny;
            }
        }
        double in[18], sol[SFMI_TMPL_UPRIGHT3PT_NSOL * 3], gR[SFMI_TMPL_UPRIGHT3PT_NSOL][9];
        double gt[SFMI_TMPL_UPRIGHT3PT_NSOL][3];
        int gfront[SFMI_TMPL_UPRIGHT3PT_NSOL];
        for (int i = 0; i < 9; i++) {
            in[i] = x1[i];
            in[9 + i] = x2[i];
        }
        int ng = sfmi_tmpl_upright3pt(in, sol);
        SFM_CHECK(ng >= 0 && ng <= SFMI_TMPL_UPRIGHT3PT_NSOL);
        if (ng < 0)
            continue;
        for (int j = 0; j < ng; j++) {
            double q = sol[3 * j], u = 1.0 + q * q;
            double Rj[9] = {(1 - q * q) / u, 0, 2 * q / u, 0, 1, 0, -2 * q / u, 0, (1 - q * q) / u};
            double l = sqrt(sol[3 * j + 1] * sol[3 * j + 1] + sol[3 * j + 2] * sol[3 * j + 2] + 1.0);
            for (int i = 0; i < 9; i++)
                gR[j][i] = Rj[i];
            gt[j][0] = sol[3 * j + 1] / l;
            gt[j][1] = sol[3 * j + 2] / l;
            gt[j][2] = 1.0 / l;
            gfront[j] = upright_in_front(x1, x2, gR[j], gt[j]);
        }
        sfm_pose poses[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS];
        double e_y[3] = {0.0, 1.0, 0.0};
        int nc = sfm_relpose_upright_3pt(x1, x2, e_y, e_y, poses);
        SFM_CHECK(nc >= 0);
        /* match the two sets: t up to sign (the template fixes t_z = 1) */
        int used[SFMI_TMPL_UPRIGHT3PT_NSOL] = {0}, ok = 1, have_truth = 0;
        for (int k = 0; k < nc; k++) {
            int hit = 0;
            for (int j = 0; j < ng && !hit; j++) {
                double e = 0.0, ep = 0.0, em = 0.0;
                for (int i = 0; i < 9; i++)
                    e = fmax(e, fabs(poses[k].R[i] - gR[j][i]));
                for (int i = 0; i < 3; i++) {
                    ep = fmax(ep, fabs(poses[k].t[i] - gt[j][i]));
                    em = fmax(em, fabs(poses[k].t[i] + gt[j][i]));
                }
                if (e < 1e-5 && fmin(ep, em) < 1e-5 && !used[j])
                    hit = used[j] = 1;
            }
            ok &= hit;
            double e = 0.0;
            for (int i = 0; i < 9; i++)
                e = fmax(e, fabs(poses[k].R[i] - R[i]));
            for (int i = 0; i < 3; i++)
                e = fmax(e, fabs(poses[k].t[i] - tv[i]));
            have_truth |= e < 1e-6;
        }
        for (int j = 0; j < ng; j++)
            ok &= used[j] || !gfront[j];
        same += ok;
        truth += have_truth;
    }
    SFM_TEST_LOG("same solution set in %d of %d, truth among the closed-form poses in %d",
                 same, trials, truth);
    SFM_CHECK_MSG(same >= trials - trials / 200, "same set in %d of %d", same, trials);
    SFM_CHECK(truth >= trials - trials / 200);
}
