/* SPRT model verification: Chum & Matas, "Optimal randomized RANSAC", PAMI
 * 2008, sections 3-4 (decision threshold A, eq. 18; adaptive delta). */
#include "robust/sprt.h"

#include <math.h>
#include "core/dmath.h"

void sfmi_sprt_init(sfmi_sprt *s, double eps, double delta)
{
    s->eps = eps;
    s->delta = delta;
    s->bad_tested = 0.0;
    s->bad_consistent = 0.0;
    s->models_per_sample = 1.0;
    s->n_samples = 0.0;
    sfmi_sprt_update(s);
}

void sfmi_sprt_update(sfmi_sprt *s)
{
    double eps = s->eps, delta = s->delta;
    if (!(eps > delta * 1.05) || eps >= 1.0 || delta <= 0.0) {
        s->active = 0;
        s->A = HUGE_VAL;
        s->mult_in = 1.0;
        s->mult_out = 1.0;
        return;
    }
    s->active = 1;
    s->mult_in = delta / eps;
    s->mult_out = (1.0 - delta) / (1.0 - eps);
    /* C: the Kullback-Leibler divergence between the two Bernoulli laws. */
    double C = (1.0 - delta) * sfmi_log((1.0 - delta) / (1.0 - eps)) + delta * sfmi_log(delta / eps);
    double ms = s->models_per_sample > 1.0 ? s->models_per_sample : 1.0;
    double K = SFM_SPRT_MODEL_COST * C / ms;
    double A = K + 1.0;
    for (int i = 0; i < 20; i++) {
        double next = K + 1.0 + sfmi_log(A);
        if (fabs(next - A) < 1e-6 * A) {
            A = next;
            break;
        }
        A = next;
    }
    s->A = A > 1.0 + 1e-9 ? A : 1.0 + 1e-9;
}

void sfmi_sprt_record_rejection(sfmi_sprt *s, int tested, int consistent)
{
    s->bad_tested += tested;
    s->bad_consistent += consistent;
    if (s->bad_tested < 100.0)
        return;
    double d = s->bad_consistent / s->bad_tested;
    if (d < 1e-4)
        d = 1e-4;
    if (d > 0.5)
        d = 0.5;
    if (fabs(d - s->delta) > 0.1 * s->delta) {
        s->delta = d;
        sfmi_sprt_update(s);
    }
}

void sfmi_sprt_record_models(sfmi_sprt *s, int n_models)
{
    s->n_samples += 1.0;
    s->models_per_sample += ((double)n_models - s->models_per_sample) / s->n_samples;
}

double sfmi_sprt_pass_probability(const sfmi_sprt *s)
{
    if (!s->active)
        return 1.0;
    return 1.0 - 1.0 / s->A;
}
