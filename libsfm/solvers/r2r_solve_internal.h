/*
 * Internal: the reduction behind sfm_r2r_solve, exposed to the tests so that
 * the symmetry reduction can be checked without the base-system solvers.
 *
 * Canonical frames: with the robots exchanged (swap) and the sequence
 * re-referenced to the step placed first (ref, its ego-motion after the
 * exchange: R1r, t1r, R2r, t2r), the unknown becomes
 *   swap:        Cs = C^T, ps = -C^T p     (else Cs = C, ps = p)
 *   re-reference: C' = R1r^T Cs R2r,  p' = R1r^T (Cs t2r + ps - t1r)
 * and every ego-motion (R, t) of a robot becomes (Rr^T R, Rr^T (t - tr)).
 */
#ifndef SFM_SOLVERS_R2R_SOLVE_INTERNAL_H
#define SFM_SOLVERS_R2R_SOLVE_INTERNAL_H

#include "solvers/r2r_internal.h"

typedef struct sfmi_r2r_canon {
    int sys;   /* sfm_r2r_system */
    int swap;  /* 1: robots exchanged */
    int n;     /* canonical steps */
    int idx[6]; /* index, in the steps given, of each canonical step */
    double R1r[9], t1r[3], R2r[9], t2r[3]; /* reference ego-motion, after the exchange */
    sfm_r2r_step steps[6]; /* canonical steps: pattern order, unit bearings */
} sfmi_r2r_canon;

/* The canonical form of the measurements use[i] (a has-mask, subset of
 * steps[i].has; 0 = step unused) of n steps whose equations add up to six.
 * Steps must already be valid (finite, rotations, positive d, nonzero b).
 * Returns the sfm_r2r_system (>= 1) or SFM_E_ARGUMENT (not six equations). */
int sfmi_r2r_canonicalize(const sfm_r2r_step *steps, const unsigned *use, int n,
                          sfmi_r2r_canon *c);
/* (C, p) in the input frames <-> in the canonical frames of c. In place is
 * allowed (out == in). */
void sfmi_r2r_to_canonical(const sfmi_r2r_canon *c, const sfm_r2r_transform *in,
                           sfm_r2r_transform *out);
void sfmi_r2r_from_canonical(const sfmi_r2r_canon *c, const sfm_r2r_transform *in,
                             sfm_r2r_transform *out);

/* 1 when a turn of C about one robot's line of motion is unseen: robot 2's
 * positions on one straight line (or still, within 1e-6 of the scene's
 * scale) and no b2 among the measurements use[k] (NULL: each step's has),
 * or robot 1's and no b1. Base solvers call it on their own steps too. */
int sfmi_r2r_motion_degenerate(const sfm_r2r_step *s, const unsigned *use, int n);

/* The canonical pattern of each base system (index = sfm_r2r_system). */
extern const unsigned char sfmi_r2r_patterns[SFM_R2R_SYS_COUNT_][7]; /* n, masks... */

/* sfm_r2r_solve over a given registry (index = sfm_r2r_system, entry 0
 * unused). A descriptor with max_solutions 0 is a placeholder: the system
 * is not built, its solver answers SFM_E_UNSUPPORTED. */
typedef const sfmi_r2r_system_desc *const sfmi_r2r_registry[SFM_R2R_SYS_COUNT_];
extern const sfmi_r2r_registry sfmi_r2r_table;
size_t sfmi_r2r_solve_ws_size_with(const sfmi_r2r_system_desc *const *table, int n_steps);
int sfmi_r2r_solve_with(const sfmi_r2r_system_desc *const *table, const sfm_r2r_step *steps,
                        int n_steps, sfm_r2r_transform *out, void *ws, size_t ws_size);

#endif
