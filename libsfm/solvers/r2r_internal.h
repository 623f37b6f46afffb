/*
 * Internal: the base-system solvers behind sfm_r2r_solve.
 *
 * Each base system (sfm_r2r_system) has one solver file,
 * libsfm/solvers/r2r_<pattern>.c, defining one descriptor. The solver takes
 * the steps in the system's canonical order and form: steps[0] carries the
 * identity ego-motion (the dispatcher re-references the sequence to the step
 * it puts first), the robots are already exchanged so that the pattern reads
 * as in sfm_r2r_system, and the measurements each step carries are exactly
 * the pattern's (bearings unit length, distances positive). It writes every
 * real solution (C proper, p) from index 0 and returns the count, or a
 * negative sfm_status (SFM_E_SINGULAR for a template that is singular for
 * these data). It uses at most ws_doubles doubles of ws (8-byte aligned) and
 * at most 16 KiB of stack.
 */
#ifndef SFM_SOLVERS_R2R_INTERNAL_H
#define SFM_SOLVERS_R2R_INTERNAL_H

#include <stddef.h>

#include "sfm/sfm_r2r.h"

typedef int (*sfmi_r2r_solve_fn)(const sfm_r2r_step *steps, sfm_r2r_transform *out,
                                 double *ws);

typedef struct sfmi_r2r_system_desc {
    sfm_r2r_system id;
    int n_steps;               /* steps in the canonical pattern */
    unsigned pattern[6];       /* has-mask of each canonical step */
    int max_solutions;         /* complex solution count (the paper's) */
    size_t ws_doubles;         /* work memory the solver needs */
    sfmi_r2r_solve_fn solve;
    const char *name;          /* "db1_d_d_d", ... */
} sfmi_r2r_system_desc;

/* The solver of a base system with no finite solution set (DB1_DB1,
 * DB1_DB2: six equations of rank 5): SFM_E_DEGENERATE, nothing written. */
int sfmi_r2r_solve_rank5(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws);

/* One descriptor per solver file; the table in r2r_solve.c lists them by id. */
extern const sfmi_r2r_system_desc sfmi_r2r_db1b2_d;
extern const sfmi_r2r_system_desc sfmi_r2r_b1b2_b1;
extern const sfmi_r2r_system_desc sfmi_r2r_b1b2_d_d;
extern const sfmi_r2r_system_desc sfmi_r2r_db1_db1;
extern const sfmi_r2r_system_desc sfmi_r2r_db1_db2;
extern const sfmi_r2r_system_desc sfmi_r2r_db1_b1_d;
extern const sfmi_r2r_system_desc sfmi_r2r_db1_b2_d;
extern const sfmi_r2r_system_desc sfmi_r2r_db1_d_d_d;
extern const sfmi_r2r_system_desc sfmi_r2r_b1_b1_b1;
extern const sfmi_r2r_system_desc sfmi_r2r_b1_b1_b2;
extern const sfmi_r2r_system_desc sfmi_r2r_b1_b1_d_d;
extern const sfmi_r2r_system_desc sfmi_r2r_b1_b2_d_d;
extern const sfmi_r2r_system_desc sfmi_r2r_b1_d_d_d_d;
extern const sfmi_r2r_system_desc sfmi_r2r_d6;

#endif
