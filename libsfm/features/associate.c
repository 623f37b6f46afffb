/*
 * Three-view cyclic association: a view-1 feature i becomes a track
 * (i, j, k) when its match j in view 2 maps to k in view 3 and k maps back
 * to i in view 1. A wrong match anywhere on the cycle rarely closes it, so
 * the cycle is a cheap consistency check before any geometry.
 */
#include "core/arena.h"
#include "sfm/sfm_features.h"

typedef struct assoc_ws {
    int32_t *f12, *f23, *f31;
} assoc_ws;

static void carve(sfmi_arena *a, int n1, int n2, int n3, assoc_ws *m)
{
    m->f12 = SFM_ARENA_ARRAY(a, int32_t, n1);
    m->f23 = SFM_ARENA_ARRAY(a, int32_t, n2);
    m->f31 = SFM_ARENA_ARRAY(a, int32_t, n3);
}

size_t sfm_features_associate_workspace_size(int n1, int n2, int n3)
{
    if (n1 < 0 || n2 < 0 || n3 < 0)
        return 0;
    sfmi_arena a;
    assoc_ws m;
    sfmi_arena_measure(&a);
    carve(&a, n1, n2, n3, &m);
    return sfmi_arena_required(&a);
}

/* Fills f (size n_from, preset to -1) from pairs; 0 on a bad or repeated index. */
static int fill(int32_t *f, int n_from, int n_to, const int *pairs, int n)
{
    for (int i = 0; i < n_from; i++)
        f[i] = -1;
    for (int k = 0; k < n; k++) {
        const int s = pairs[2 * k], d = pairs[2 * k + 1];
        if (s < 0 || s >= n_from || d < 0 || d >= n_to || f[s] >= 0)
            return 0;
        f[s] = d;
    }
    return 1;
}

int sfm_features_associate_three_views(const int *m12, int n12, const int *m23, int n23, const int *m31, int n31,
                                       int n1, int n2, int n3, int *out, int capacity, void *ws, size_t ws_size)
{
    if (ws == NULL || out == NULL || n12 < 0 || n23 < 0 || n31 < 0 || n1 < 0 || n2 < 0 || n3 < 0 ||
        (m12 == NULL && n12 > 0) || (m23 == NULL && n23 > 0) || (m31 == NULL && n31 > 0))
        return SFM_E_ARGUMENT;
    int need_cap = n12 < n23 ? n12 : n23;
    need_cap = n31 < need_cap ? n31 : need_cap;
    if (capacity < need_cap)
        return SFM_E_CAPACITY;
    const size_t need = sfm_features_associate_workspace_size(n1, n2, n3);
    if (need == 0 || ws_size < need)
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    assoc_ws m;
    sfmi_arena_init(&a, ws, ws_size);
    carve(&a, n1, n2, n3, &m);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    if (!fill(m.f12, n1, n2, m12, n12) || !fill(m.f23, n2, n3, m23, n23) || !fill(m.f31, n3, n1, m31, n31))
        return SFM_E_ARGUMENT;
    int n = 0;
    for (int i = 0; i < n1; i++) {
        const int j = m.f12[i];
        if (j < 0)
            continue;
        const int k = m.f23[j];
        if (k < 0 || m.f31[k] != i)
            continue;
        out[3 * n] = i;
        out[3 * n + 1] = j;
        out[3 * n + 2] = k;
        n++;
    }
    return n;
}
