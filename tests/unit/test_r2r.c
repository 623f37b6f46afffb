/*
 * Generated action-matrix solvers against known answers: System 10 of Zhou &
 * Roumeliotis (three equations u_k^T C v_k = c_k built from a true rotation)
 * must return the true Cayley vector among its solutions.
 */
#include <math.h>

#include "sfm_test.h"
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
        int n = sfmi_tmpl_sys10(in, sol);
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
