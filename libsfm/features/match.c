/*
 * Brute-force Hamming matching with Lowe's ratio test (Lowe, IJCV 2004) and
 * a mutual nearest-neighbour check.
 *
 * One pass over the n1 x n2 distance matrix gives both directions: each
 * query keeps its best and second-best distance (rows), each train
 * descriptor its best query (columns). Queries go in blocks of 4 so every
 * train descriptor read from memory serves four queries held in registers;
 * the train set streams through the cache once per block.
 */
#include "core/arena.h"
#include "features/hamming.h"
#include "sfm/sfm_features.h"

#include <math.h>

#define QB 4

int sfm_features_hamming(const uint8_t *a, const uint8_t *b)
{
    if (a == NULL || b == NULL)
        return SFM_E_ARGUMENT;
    return sfmi_feat_hamming256(a, b);
}

int sfm_features_default_match_params(sfm_match_params *p)
{
    if (p == NULL)
        return SFM_E_ARGUMENT;
    p->ratio = 0.8;
    p->mutual = 1;
    p->max_distance = 256;
    return SFM_OK;
}

typedef struct match_ws {
    int32_t *row_best, *row_idx, *row_second;
    int32_t *col_best, *col_idx;
} match_ws;

static void carve(sfmi_arena *a, int n1, int n2, match_ws *m)
{
    m->row_best = SFM_ARENA_ARRAY(a, int32_t, n1);
    m->row_idx = SFM_ARENA_ARRAY(a, int32_t, n1);
    m->row_second = SFM_ARENA_ARRAY(a, int32_t, n1);
    m->col_best = SFM_ARENA_ARRAY(a, int32_t, n2);
    m->col_idx = SFM_ARENA_ARRAY(a, int32_t, n2);
}

size_t sfm_features_match_workspace_size(int n1, int n2)
{
    if (n1 < 0 || n2 < 0)
        return 0;
    sfmi_arena a;
    match_ws m;
    sfmi_arena_measure(&a);
    carve(&a, n1, n2, &m);
    return sfmi_arena_required(&a);
}

/* Rows [i0, i0 + nq) (nq <= QB) against every train descriptor. */
static void block(const uint8_t *d1, int i0, int nq, const uint8_t *d2, int n2, match_ws *m)
{
    uint64_t q[QB][4];
    int b1[QB], b2[QB], bi[QB];
    for (int k = 0; k < QB; k++) {
        const uint8_t *src = d1 + (size_t)(i0 + (k < nq ? k : 0)) * 32;
        for (int w = 0; w < 4; w++)
            q[k][w] = sfmi_feat_load64(src + 8 * w);
        b1[k] = b2[k] = 257;
        bi[k] = -1;
    }
    int32_t *cb = m->col_best, *ci = m->col_idx;
    for (int j = 0; j < n2; j++) {
        const uint8_t *t = d2 + (size_t)j * 32;
        const uint64_t t0 = sfmi_feat_load64(t), t1 = sfmi_feat_load64(t + 8), t2 = sfmi_feat_load64(t + 16),
                       t3 = sfmi_feat_load64(t + 24);
        int d[QB];
        for (int k = 0; k < QB; k++)
            d[k] = sfmi_feat_popcount256(q[k][0] ^ t0, q[k][1] ^ t1, q[k][2] ^ t2, q[k][3] ^ t3);
        int cbest = cb[j], cidx = ci[j];
        for (int k = 0; k < nq; k++) {
            const int dk = d[k];
            if (dk < b1[k]) {
                b2[k] = b1[k];
                b1[k] = dk;
                bi[k] = j;
            } else if (dk < b2[k]) {
                b2[k] = dk;
            }
            if (dk < cbest) {
                cbest = dk;
                cidx = i0 + k;
            }
        }
        cb[j] = cbest;
        ci[j] = cidx;
    }
    for (int k = 0; k < nq; k++) {
        m->row_best[i0 + k] = b1[k];
        m->row_second[i0 + k] = b2[k];
        m->row_idx[i0 + k] = bi[k];
    }
}

int sfm_features_match(const uint8_t *d1, int n1, const uint8_t *d2, int n2, const sfm_match_params *p,
                       int *matches, int *distances, int capacity, void *ws, size_t ws_size)
{
    if (p == NULL || ws == NULL || matches == NULL || n1 < 0 || n2 < 0 || (d1 == NULL && n1 > 0) ||
        (d2 == NULL && n2 > 0))
        return SFM_E_ARGUMENT;
    if (!isfinite(p->ratio) || !(p->ratio > 0.0) || p->ratio > 1.0 || p->max_distance < 0 ||
        p->max_distance > 256 || (p->mutual != 0 && p->mutual != 1))
        return SFM_E_ARGUMENT;
    if (capacity < n1)
        return SFM_E_CAPACITY;
    const size_t need = sfm_features_match_workspace_size(n1, n2);
    if (need == 0 || ws_size < need)
        return SFM_E_WORKSPACE;
    if (n1 == 0 || n2 == 0)
        return 0;
    sfmi_arena a;
    match_ws m;
    sfmi_arena_init(&a, ws, ws_size);
    carve(&a, n1, n2, &m);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    for (int j = 0; j < n2; j++) {
        m.col_best[j] = 257;
        m.col_idx[j] = -1;
    }
    for (int i0 = 0; i0 < n1; i0 += QB)
        block(d1, i0, n1 - i0 < QB ? n1 - i0 : QB, d2, n2, &m);
    int n = 0;
    for (int i = 0; i < n1; i++) {
        const int j = m.row_idx[i], b = m.row_best[i], s = m.row_second[i];
        if (j < 0 || b > p->max_distance)
            continue;
        /* second == 257 when n2 == 1: no competitor, the test passes */
        if (p->ratio < 1.0 && s <= 256 && !((double)b < p->ratio * (double)s))
            continue;
        if (p->mutual && m.col_idx[j] != i)
            continue;
        matches[2 * n] = i;
        matches[2 * n + 1] = j;
        if (distances != NULL)
            distances[n] = b;
        n++;
    }
    return n;
}
