/*
 * Internal: Wald's sequential probability ratio test for RANSAC model
 * verification (Chum & Matas, "Optimal randomized RANSAC", PAMI 2008).
 *
 * A model is tested point by point. Under H_g (good model) a point is
 * consistent with probability eps, under H_b (bad model) with probability
 * delta. The likelihood ratio lambda is multiplied by delta/eps for a
 * consistent point and by (1-delta)/(1-eps) otherwise; the model is rejected
 * as soon as lambda > A. A is the optimal threshold of the paper (eq. 18):
 * A = K + 1 + ln A with K = t_M * C / m_S, solved by fixed-point iteration.
 */
#ifndef SFM_ROBUST_SPRT_H
#define SFM_ROBUST_SPRT_H

typedef struct sfmi_sprt {
    double eps;        /* inlier ratio of a good model */
    double delta;      /* consistency ratio of a bad model */
    double A;          /* decision threshold on lambda */
    double mult_in;    /* delta / eps */
    double mult_out;   /* (1 - delta) / (1 - eps) */
    int active;        /* 0 when eps <= delta: the test cannot tell them apart */
    double bad_tested; /* points tested in rejected models */
    double bad_consistent;
    double models_per_sample; /* running mean m_S */
    double n_samples;
} sfmi_sprt;

/* Time to compute one sample's models, in units of one point verification. */
#define SFM_SPRT_MODEL_COST 200.0

void sfmi_sprt_init(sfmi_sprt *s, double eps, double delta);
/* Recompute A and the multipliers for the current eps and delta. */
void sfmi_sprt_update(sfmi_sprt *s);
/* Record a rejected model (tested points, how many were consistent); re-tunes
 * delta when the estimate has moved by more than 10 %. */
void sfmi_sprt_record_rejection(sfmi_sprt *s, int tested, int consistent);
/* Record the number of models a sample produced. */
void sfmi_sprt_record_models(sfmi_sprt *s, int n_models);
/* Probability that a good model passes the test (1 - 1/A), 1 when inactive. */
double sfmi_sprt_pass_probability(const sfmi_sprt *s);

#endif
