/*
 * Null space as the right singular vectors of the smallest singular values
 * (one-sided Jacobi SVD; for m < n the n - m trailing vectors come from the
 * orthogonal completion and have singular value 0).
 */
#include "core/arena.h"
#include "core/linalg_util.h"
#include "core/svd_internal.h"

typedef struct ns_ws {
    double *V;     /* n x n */
    double *S;     /* min(m, n) */
    void *svd_ws;  /* sfm_svd_workspace_size(m, n) bytes */
    size_t svd_size;
} ns_ws;

static void ns_layout(sfmi_arena *a, int m, int n, ns_ws *w)
{
    w->V = SFM_ARENA_ARRAY(a, double, (size_t)n * n);
    w->S = SFM_ARENA_ARRAY(a, double, m < n ? m : n);
    w->svd_size = sfm_svd_workspace_size(m, n);
    w->svd_ws = sfmi_arena_alloc(a, w->svd_size);
}

size_t sfm_nullspace_workspace_size(int m, int n)
{
    if (!sfmi_la_dim_ok(m) || !sfmi_la_dim_ok(n))
        return 0;
    sfmi_arena a;
    ns_ws w;
    sfmi_arena_measure(&a);
    ns_layout(&a, m, n, &w);
    return sfmi_arena_required(&a);
}

int sfm_nullspace(const double *A, int m, int n, int k, double *N, double *S, void *ws,
                  size_t ws_size)
{
    if (A == NULL || N == NULL || ws == NULL || !sfmi_la_dim_ok(m) || !sfmi_la_dim_ok(n) ||
        k < 1 || k > n)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(A, (size_t)m * (size_t)n))
        return SFM_E_NONFINITE;
    sfmi_arena a;
    ns_ws w;
    if (ws_size < sfm_nullspace_workspace_size(m, n))
        return SFM_E_WORKSPACE;
    sfmi_arena_init(&a, ws, ws_size);
    ns_layout(&a, m, n, &w);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    int st = sfmi_svd_core(A, m, n, NULL, w.S, w.V, w.svd_ws, w.svd_size);
    if (st != SFM_OK)
        return st;
    const int p = m < n ? m : n;
    for (int j = 0; j < k; j++) {
        int col = n - 1 - j; /* smallest first */
        for (int i = 0; i < n; i++)
            N[(size_t)i * k + j] = w.V[(size_t)i * n + col];
        if (S != NULL)
            S[j] = col < p ? w.S[col] : 0.0;
    }
    return SFM_OK;
}
