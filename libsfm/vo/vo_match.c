/* Guided matching: keypoints are binned in a uniform grid over their ideal
 * pixels, and a query (a predicted position plus a descriptor) looks only at
 * the cells its search radius touches, instead of every keypoint. */
#include <math.h>

#include "vo/vo_internal.h"

/* Clamped in double before the cast: a search radius of 1e300 (finite,
 * accepted by sfm_vo_init) puts uv +- radius far outside the int range,
 * where the conversion is undefined (x86 gives INT_MIN, which clamped the
 * upper edge to cell 0 and searched one cell instead of all). */
static int cell_of(double v, int n_cells)
{
    double c = floor(v / VO_GRID_CELL);
    if (!(c >= 0.0))
        return 0;
    if (c >= (double)n_cells)
        return n_cells - 1;
    return (int)c;
}

void sfmi_vo_grid_build(vo_grid *g, const double *px, const uint8_t *valid, int n)
{
    int nc = g->gw * g->gh;
    for (int c = 0; c <= nc; c++)
        g->start[c] = 0;
    for (int i = 0; i < n; i++) {
        if (!valid[i]) {
            g->cell[i] = -1;
            continue;
        }
        int c = cell_of(px[2 * i + 1], g->gh) * g->gw + cell_of(px[2 * i], g->gw);
        g->cell[i] = c;
        g->start[c + 1]++;
    }
    for (int c = 0; c < nc; c++)
        g->start[c + 1] += g->start[c];
    /* counting sort, stable in the keypoint index */
    for (int i = 0; i < n; i++) {
        int c = g->cell[i];
        if (c >= 0)
            g->items[g->start[c]++] = i;
    }
    for (int c = nc; c > 0; c--)
        g->start[c] = g->start[c - 1];
    g->start[0] = 0;
}

int sfmi_vo_grid_search(const vo_grid *g, const double *px, const uint8_t *desc,
                        const double uv[2], double radius, const uint8_t *d, int max_d,
                        double ratio, const int *skip, const double *line, double line_tol,
                        int *dist)
{
    int x0 = cell_of(uv[0] - radius, g->gw), x1 = cell_of(uv[0] + radius, g->gw);
    int y0 = cell_of(uv[1] - radius, g->gh), y1 = cell_of(uv[1] + radius, g->gh);
    double r2 = radius * radius;
    int best = -1, bd = 257, sd = 257;
    for (int cy = y0; cy <= y1; cy++) {
        for (int cx = x0; cx <= x1; cx++) {
            int c = cy * g->gw + cx;
            for (int k = g->start[c]; k < g->start[c + 1]; k++) {
                int i = g->items[k];
                if (skip != NULL && skip[i] >= 0)
                    continue;
                double dx = px[2 * i] - uv[0], dy = px[2 * i + 1] - uv[1];
                if (dx * dx + dy * dy > r2)
                    continue;
                if (line != NULL &&
                    fabs(line[0] * px[2 * i] + line[1] * px[2 * i + 1] + line[2]) > line_tol)
                    continue;
                int h = sfm_features_hamming(d, desc + (size_t)SFM_FEATURES_DESC_BYTES * i);
                if (h < bd) {
                    sd = bd;
                    bd = h;
                    best = i;
                } else if (h < sd) {
                    sd = h;
                }
            }
        }
    }
    if (best < 0 || bd > max_d)
        return -1;
    if (sd <= 256 && !((double)bd < ratio * (double)sd))
        return -1;
    *dist = bd;
    return best;
}
