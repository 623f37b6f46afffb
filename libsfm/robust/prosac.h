/*
 * Internal: PROSAC sampling (Chum & Matas, "Matching with PROSAC - progressive
 * sample consensus", CVPR 2005). Points are ranked by quality; samples are
 * drawn from a top-n subset that grows on the schedule T'_n of the paper, so
 * the best-ranked points are tried first and sampling becomes uniform over
 * all points once n reaches N.
 */
#ifndef SFM_ROBUST_PROSAC_H
#define SFM_ROBUST_PROSAC_H

#include "sfm/sfm_rng.h"

typedef struct sfmi_prosac {
    int N;         /* number of points */
    int m;         /* sample size */
    int n;         /* current subset size */
    int t;         /* samples drawn */
    double Tn;     /* T_n of the paper (real valued) */
    double Tn_prime;
} sfmi_prosac;

/* Sort order[0..N) by decreasing quality (ties by increasing index, so the
 * order is unique). In place heap sort: no extra memory. */
void sfmi_prosac_sort(int *order, const double *quality, int N);
void sfmi_prosac_init(sfmi_prosac *p, int N, int m);
/* Draw the next sample as ranks (positions in the sorted order) into out[m]. */
void sfmi_prosac_sample(sfmi_prosac *p, sfm_rng *rng, int *out);

#endif
