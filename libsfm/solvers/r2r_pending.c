/*
 * PLACEHOLDERS, to be deleted when the base-system solvers are merged.
 *
 * One descriptor per base system whose solver file (libsfm/solvers/
 * r2r_<name>.c) is not on this branch yet, so that the registry table in
 * r2r_solve.c links. Each returns SFM_E_UNSUPPORTED; sfm_r2r_solve passes
 * that status on. Remove an entry when its r2r_<name>.c lands (the two
 * definitions would otherwise collide at link time).
 */
#include "sfm/sfm_common.h"
#include "solvers/r2r_internal.h"

static int sfmi_r2r_pending_solve(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)steps;
    (void)out;
    (void)ws;
    return SFM_E_UNSUPPORTED;
}

#define SFMI_R2R_PENDING(var, sys, n, p0, p1, p2, p3, p4, p5, nsol)                         \
    const sfmi_r2r_system_desc var = {sys, n, {p0, p1, p2, p3, p4, p5}, nsol, 0,           \
                                      sfmi_r2r_pending_solve, "pending"}

#define D_ SFM_R2R_D
#define B1_ SFM_R2R_B1
#define B2_ SFM_R2R_B2

/* PLACEHOLDER r2r-b */
SFMI_R2R_PENDING(sfmi_r2r_d6, SFM_R2R_SYS_D6, 6, D_, D_, D_, D_, D_, D_, 0);
