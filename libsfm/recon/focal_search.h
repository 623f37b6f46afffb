/*
 * Internal: the one-dimensional focal search shared by the metric stage of
 * the uncalibrated pipelines (metric_upgrade.c) and the self-calibration
 * with points (selfcal_sweep.c): a coarse sweep of candidate focal lengths
 * scored by the caller, then a golden-section search on log f. Not API.
 */
#ifndef SFM_RECON_FOCAL_SEARCH_H
#define SFM_RECON_FOCAL_SEARCH_H

/* Cost of focal length f (HUGE_VAL when none can be had); may change the
 * caller's state (called in the order the candidates are listed). */
typedef double (*sfmi_focal_score_fn)(void *ctx, double f);

/* cost[k] = score(f[k]) for k = 0..count-1 in order; the index of the
 * smallest finite cost (the first of equals), -1 when none is finite. */
int sfmi_focal_sweep(sfmi_focal_score_fn score, void *ctx, const double *f, int count, double *cost);

/* Golden-section search for the minimum of score(exp(u)) on [lo, hi] with
 * `steps` reductions of the bracket (Kiefer 1953); u[0] <= u[1] the last two
 * interior points, s their costs. Equal costs keep the lower part of the
 * bracket when ties_low, else the upper part. */
void sfmi_focal_golden(sfmi_focal_score_fn score, void *ctx, double lo, double hi, int steps, int ties_low,
                       double u[2], double s[2]);

#endif
