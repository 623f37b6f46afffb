/* PROSAC: Chum & Matas, CVPR 2005, section 2 (growth function and sampling). */
#include "robust/prosac.h"

#include <math.h>

/* Iterations after which sampling is uniform over all points (T_N). */
#define PROSAC_TN 200000.0

/* a ranks before b: higher quality, then lower index. */
static int before(const double *q, int a, int b)
{
    return q[a] > q[b] || (q[a] == q[b] && a < b);
}

static void sift_down(int *h, const double *q, int root, int n)
{
    for (;;) {
        int c = 2 * root + 1;
        if (c >= n)
            return;
        /* min-heap in the "before" order puts the worst at the root */
        if (c + 1 < n && before(q, h[c], h[c + 1]))
            c++;
        if (!before(q, h[root], h[c]))
            return;
        int tmp = h[root];
        h[root] = h[c];
        h[c] = tmp;
        root = c;
    }
}

void sfmi_prosac_sort(int *order, const double *quality, int N)
{
    for (int i = 0; i < N; i++)
        order[i] = i;
    /* heap whose root is the element that ranks last */
    for (int i = N / 2 - 1; i >= 0; i--)
        sift_down(order, quality, i, N);
    for (int end = N - 1; end > 0; end--) {
        int tmp = order[0];
        order[0] = order[end];
        order[end] = tmp;
        sift_down(order, quality, 0, end);
    }
}

void sfmi_prosac_init(sfmi_prosac *p, int N, int m)
{
    p->N = N;
    p->m = m;
    p->n = m;
    p->t = 0;
    /* T_m = T_N * prod_{i<m} (m - i) / (N - i) */
    double T = PROSAC_TN;
    for (int i = 0; i < m; i++)
        T *= (double)(m - i) / (double)(N - i);
    p->Tn = T;
    p->Tn_prime = 1.0;
}

static int contains(const int *a, int k, int v)
{
    for (int i = 0; i < k; i++)
        if (a[i] == v)
            return 1;
    return 0;
}

static void draw_distinct(sfm_rng *rng, int range, int k, int *out, int start)
{
    for (int i = start; i < start + k; i++) {
        int v;
        do {
            v = (int)sfm_rng_bounded(rng, (uint32_t)range);
        } while (contains(out, i, v));
        out[i] = v;
    }
}

void sfmi_prosac_sample(sfmi_prosac *p, sfm_rng *rng, int *out)
{
    p->t++;
    if (p->n >= p->N || (double)p->t > PROSAC_TN) {
        draw_distinct(rng, p->N, p->m, out, 0);
        return;
    }
    if ((double)p->t > p->Tn_prime && p->n < p->N) {
        double next = p->Tn * (double)(p->n + 1) / (double)(p->n + 1 - p->m);
        p->n++;
        p->Tn_prime += ceil(next - p->Tn);
        p->Tn = next;
    }
    if (p->Tn_prime < (double)p->t) {
        draw_distinct(rng, p->n, p->m, out, 0);
    } else {
        /* m - 1 from the top n - 1 and the n-th point itself */
        draw_distinct(rng, p->n - 1, p->m - 1, out, 0);
        out[p->m - 1] = p->n - 1;
    }
}
